//! The bumper's marks in unknown mode: a person who walks into the robot
//! is marked like a table's crossbar the lidar cannot see, and those
//! marks can close a narrow place around the robot; and people who box
//! the robot in. Checked on the truth.

mod truth;

use host_sim::run::mission::{run_mission, MissionOptions, MissionReport};
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use robovac::mission::MapMode;
use truth::check_truth;

/// The home flat, unknown mode, 3 people, realistic noise. With seed 11,
/// at 258 s a person walked into the robot's side in the 0.8 m wide
/// pocket at (5.9, 0.7) m; the bump was marked (3 cells), and from 376 s
/// the robot was boxed in on its map. Before the marks were forgotten the
/// edge pass restarted "boxed in" every 0.5 s for 150 s and the mission
/// failed with `NoWayHome` at 619 s, 18.5 % covered. Now the marks are
/// forgotten after 5 s boxed in (`EvidenceMap::forget_contacts`). Since
/// the edge pass drives what it once dropped (stop 44), seed 11's robot
/// is no longer bumped; seed 14's was (3 marks) until the matcher left
/// the swept floor out (`localize::trail`); seed 6's was (11 marks) until
/// unknown mode's lanes kept off walls from 4 mm (18 bumps, none marked);
/// seed 7's was (19 bumps, 3 marks) until a robot standing still kept its
/// position (`fusion::held_still`); seed 1's was (3 marks) until the guard
/// counted the nearest map cells (`Mission::cells_free`); seed 2's is
/// (3 marks), and the mission must still clean on and dock. That the
/// marks box it in is not checked here.
#[test]
fn marks_that_box_the_robot_in_are_forgotten() {
    let o = MissionOptions::new(
        suite_map("home").unwrap(),
        MapMode::Unknown,
        3,
        Noise::Realistic,
        2,
    );
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    assert!(rep.counters.bump_marks > 0, "{:?}", rep.counters);
    assert!(rep.finished && rep.docked, "{rep:?}");
    assert_eq!(rep.final_state, "Done", "{rep:?}");
    assert!(rep.coverage > 0.4, "coverage {:.4}", rep.coverage);
}

/// A real home (S6), known map, 1 person, realistic noise, seed 2 (seed
/// 11 since people walk loops of 3 waypoints at least, `MIN_LOOP`: 12
/// bumps by 600 s, none marked). The person's loop crosses a narrow passage; they wait 4 s beside the robot
/// in their way, then push past it, standing over the lidar, which then
/// sees nothing of them. Those bumps were marked as walls the lidar cannot
/// see (6 by 200 s), and a known map never forgets its marks: the robot,
/// boxed in, gave the lanes up and failed with `NoWayHome` at 560 s,
/// 8.4 % covered. A bump within 3 s of a point off the map's walls near
/// the body is now the person's, and nothing is marked. By 600 s it has
/// cleaned 30 % (31.6 % with the Bresenham beams, 29.6 % with the exact
/// walk): the bound is set well above the 8.4 % of the failure.
#[test]
fn a_person_pushing_past_the_robot_is_not_marked_as_a_wall() {
    let rep = known_mission("S6", 1, 11, 600.0);
    assert!(rep.counters.bumps > 0, "{:?}", rep.counters);
    assert_eq!(rep.counters.bump_marks, 0, "{:?}", rep.counters);
    assert!(!rep.final_state.starts_with("Failed"), "{rep:?}");
    assert!(rep.coverage > 0.25, "coverage {:.4}", rep.coverage);
}

/// A real home (l10su), known map, 1 person, realistic noise, seed 3. At
/// 340 s the person stopped 0.4 m from the robot, which stood by a wall,
/// for 45 s: every detour search found the robot boxed in. Each goal the
/// planner offered meanwhile was skipped (10 a second, 150 in all, of
/// which the 16 kept came back later), the lanes ended at 388 s and a
/// room was left unswept (93.9 % covered). Now the lanes wait for the
/// person ([`robovac::mission::BOXED_NODES`]): at 420 s the robot is still
/// on its lanes, and the whole mission covers 99.0 %. Since the follower
/// turns faster (issue 12) the run differs: one goal is abandoned by
/// 420 s (none before), and the whole mission covers 99.2 % and docks.
#[test]
fn a_person_boxing_the_robot_in_is_waited_for() {
    let rep = known_mission("l10su", 1, 3, 420.0);
    assert!(
        !rep.state_time_s.contains_key("Edge"),
        "{:?}",
        rep.state_time_s
    );
    assert!(rep.counters.skipped < 60, "{:?}", rep.counters);
    assert!(rep.counters.abandoned_retries <= 1, "{:?}", rep.counters);
}

/// The studio flat, known map, 3 people, realistic noise, seed 3. Two
/// people stood either side of the robot; the coverage planner's search
/// for its next goal expanded 11 planning cells, gave up all 66 goals
/// left, and spent both rounds of taking them up again in the same
/// second: the lanes ended, 80.3 % covered. Now a planner search that
/// gives goals up boxed in ([`robovac::mission::BOXED_PLAN_NODES`]) waits
/// for the people, and the whole mission cleans on and docks.
#[test]
fn people_boxing_the_robot_in_do_not_end_its_lanes() {
    let rep = known_mission("studio", 3, 3, 3.0 * 3600.0);
    assert!(rep.docked, "{rep:?}");
    assert!(rep.coverage > 0.97, "coverage {:.4}", rep.coverage);
    // Both rounds were spent at 192 s before; one is left now.
    assert!(rep.counters.abandoned_retries < 2, "{:?}", rep.counters);
}

/// The studio flat, unknown mode, 1 person, harsh noise, seed 1. Harsh
/// floors make part of a piece of furniture dark; its other part
/// reflects. Each bump on the dark part, at about (2.40, 1.10) m, was
/// taken as seen, because the reflecting part of the same face lay 50-70
/// mm beyond the rim: nothing was marked, the leg was planned into the
/// face again, and the robot bumped there every second or so. 3 844 bumps
/// in 3 941 s, 83.7 % covered. Now, from the third bump in one place,
/// only a point at the contact spot itself counts as seen
/// (`BELIEVE_AFTER` in `src/mission/bump.rs`): 26 bumps, 98.2 %, docked.
/// With `BELIEVE_AFTER` at 255 it fails: 425 bumps.
#[test]
fn a_face_bumped_again_and_again_is_marked() {
    let o = MissionOptions::new(
        suite_map("studio").unwrap(),
        MapMode::Unknown,
        1,
        Noise::Harsh,
        1,
    );
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    assert!(rep.counters.bump_marks > 0, "{:?}", rep.counters);
    assert!(rep.counters.bumps < 200, "{:?}", rep.counters);
    assert!(rep.coverage > 0.95, "coverage {:.4}", rep.coverage);
    assert!(rep.docked, "{rep:?}");
}

/// The home flat, unknown mode, 1 person, harsh noise, seed 3. From
/// 11 260 s, two places 4 m apart took turns: a bump at one, each taken
/// as seen by the wide test and nothing marked, a transit, a bump at the
/// other. Counting bumps only in a row never reached the third at either;
/// 136 bumps later the 3 h cleaning budget ran out at 98.3 %, 1.9 m from
/// the dock. Counted per place (`BUMP_PLACES` in `src/mission/bump.rs`),
/// the third bump at each is marked: 30 bumps, 98.5 %, docked after
/// 6 595 s of cleaning. With `BUMP_PLACES` at 1 it fails.
#[test]
fn two_places_bumped_in_turn_are_both_marked() {
    let o = MissionOptions::new(
        suite_map("home").unwrap(),
        MapMode::Unknown,
        1,
        Noise::Harsh,
        3,
    );
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    assert!(rep.counters.bumps < 60, "{:?}", rep.counters);
    assert!(rep.coverage > 0.97, "coverage {:.4}", rep.coverage);
    assert!(rep.docked, "{rep:?}");
}

/// A suite map's mission in known mode under realistic noise, without the
/// map's own no-go zones, until `max_time_s`; checked on the truth.
fn known_mission(name: &str, people: usize, seed: u64, max_time_s: f64) -> MissionReport {
    let mut map = suite_map(name).unwrap();
    host_sim::sim::zones::drop_map_zones(&mut map);
    let mut o = MissionOptions::new(map, MapMode::Known, people, Noise::Realistic, seed);
    o.max_time_s = max_time_s;
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    rep
}

/// A suite home in unknown mode under harsh noise, 1 person, without the
/// map's own no-go zones, until `max_time_s`; checked on the truth.
fn harsh_unknown(name: &str, seed: u64, max_time_s: f64) -> MissionReport {
    unknown_mission(name, Noise::Harsh, seed, max_time_s)
}

/// A suite home in unknown mode, 1 person, without the map's own no-go
/// zones, until `max_time_s`; checked on the truth.
fn unknown_mission(name: &str, noise: Noise, seed: u64, max_time_s: f64) -> MissionReport {
    let mut map = suite_map(name).unwrap();
    host_sim::sim::zones::drop_map_zones(&mut map);
    let mut o = MissionOptions::new(map, MapMode::Unknown, 1, noise, seed);
    o.max_time_s = max_time_s;
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    rep
}

/// The 1c home, unknown mode, harsh noise, 1 person, seed 8. A glass
/// pane stands free in a room; the robot bumped along it and its marks
/// spread past the pane's end, until, from 2,300 s, it stood shut in on
/// its own map by (7.1, 1.7) m. No detour had a start there, so each leg
/// drove straight to its goal under the guard, which cannot see glass:
/// 855 bumps, and the battery ran flat 4.4 m from the dock (98.4 %).
/// Now the marks around a robot with no start are forgotten
/// (`Mission::start_fine`): 55 bumps, 98.5 %, docked.
#[test]
fn a_robot_shut_in_by_its_own_marks_forgets_them() {
    let rep = harsh_unknown("1c", 8, 21_600.0);
    assert!(rep.counters.bumps < 150, "{:?}", rep.counters);
    assert!(rep.coverage > 0.95, "coverage {:.4}", rep.coverage);
    assert!(rep.docked, "{rep:?}");
}

/// The z10 home, unknown mode, realistic noise, 1 person, seed 4. At
/// 2,984 s the person stood still for 4 s, 11 mm from the body, while the
/// robot turned toward a short edge chord; the map had written them down
/// as a wall, in the squares behind their front. The guard judged their
/// hits at those squares' face (`Hit::wall_point`): 41 mm free where 14
/// mm were. As the person stepped off, the robot drove into them at
/// 2,988 s. Now a start from rest in unknown mode takes the hits ahead as
/// measured (`Mission::start_free` in `src/mission/start_check.rs`), and the
/// robot waits. `check_truth` fails on a collision of the robot's doing.
#[test]
fn a_person_written_into_the_map_is_judged_by_their_hits() {
    let rep = unknown_mission("z10", Noise::Realistic, 4, 3_000.0);
    assert!(rep.coverage > 0.8, "coverage {:.4}", rep.coverage);
}

/// The l10su home, unknown mode, harsh noise, 1 person, seed 5. The robot
/// stalled against a glass pane it cannot see and stalled again backing
/// off, so both wheels' stall marks stayed under its body; the guard held
/// every leg out (each crossed a mark), the leg was planned again the
/// same, and the way home failed (`NoWayHome`, 97.7 %, on 5cab4e4). Now
/// the guard leaves out cells under the body (`UNDER_BODY_MM` in
/// `src/mission/control.rs`): docked, 96.9 %.
#[test]
fn marks_left_under_the_body_do_not_hold_it() {
    let rep = harsh_unknown("l10su", 5, 21_600.0);
    assert!(rep.coverage > 0.95, "coverage {:.4}", rep.coverage);
    assert!(rep.docked, "{rep:?}");
}
