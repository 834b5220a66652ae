//! Whole missions on the real homes (ValetudoMap files in maps/valetudo),
//! checked on the ground truth.

mod truth;

use host_sim::run::mission::{run_mission, MissionOptions, MissionReport, MissionTrace};
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use host_sim::sim::zones::drop_map_zones;
use robovac::mission::MapMode;
use truth::check_truth;

/// A real home (the bench's name for it) in unknown mode, its owner's
/// zones left off, realistic noise, one person, `seed`: the mission run,
/// checked on the truth, finished and docked.
fn unknown_home(name: &str, seed: u64) -> (MissionReport, MissionTrace) {
    let mut map = suite_map(name).unwrap();
    drop_map_zones(&mut map);
    let o = MissionOptions::new(map, MapMode::Unknown, 1, Noise::Realistic, seed);
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    assert!(rep.finished && rep.docked, "{}", rep.final_state);
    (rep, t)
}

/// A room left known, free and never entered is cleaned after the edge
/// pass (`mission::edge`, `retry_after_edges`). First seen on the S6
/// home, unknown mode, realistic noise, 1 person, seed 2 (`bench
/// missions --maps homes`): a person pacing beside the robot at 805 s
/// made the planner give up its goals there; its completeness rescan
/// then ran while the person still stood in the passage, found the room
/// beyond it shut, and the lanes ended with nothing given up to retry:
/// 69.9 % covered. Free uncleaned planning cells now reopen the planner
/// after the edge pass: 89.8 %. Since the guard judges mapped hits at
/// full width (stop 59) seed 2 no longer leaves a room; seed 18 did
/// (85.8 % covered with the late retry switched off, 99.5 % with it) until
/// a robot standing still kept its position (`fusion::held_still`); seed
/// 20 did (one retry, 98.99 %) until only far points conditioned a match
/// in unknown mode (`localize::track`); seed 1 did until that judgement
/// applied only while the robot translates; seed 4 did until a start
/// after standing was judged by the hits ahead (`Mission::start_free`);
/// seed 1 did again until the edge pass took a contour back at most twice
/// per place (`recover::EDGE_REOPENS_PER_PLACE`); seed 2 does (seeds 2, 3,
/// 4 and 6 retry once, 9 twice, 7 three times). The scenario is pinned to a seed, so a
/// change in behaviour can move it: re-pick by running `mission --map
/// maps/valetudo/S6_….json --mode unknown --people 1 --noise realistic
/// --no-map-zones --json F` over seeds 1–9 and taking one whose
/// `counters.abandoned_retries` is above zero.
#[test]
fn a_room_found_shut_while_someone_stood_in_its_way_is_cleaned_later() {
    let (rep, _) = unknown_home("S6", 2);
    assert!(rep.counters.abandoned_retries > 0, "{:?}", rep.counters);
    assert!(rep.coverage >= 0.95, "coverage {:.4}", rep.coverage);
}

/// The robot ends on its dock even when the way home's last leg is cut
/// short (`mission::home`, `DOCK_NUDGE_MM`). The 1c home, unknown mode,
/// realistic noise, 1 person, seed 4: the person walked into the robot
/// beside the dock, the last leg ended 75 mm short, and it docked there
/// (the issue asks for 50 mm). A last straight leg now takes it onto the
/// dock. Checked on the truth: where the body ends against where it began
/// (docked, the mission starts on the dock).
#[test]
fn a_way_home_cut_short_beside_the_dock_still_ends_on_it() {
    let (_, t) = unknown_home("1c", 4);
    let (first, last) = (t.truth.first().unwrap(), t.truth.last().unwrap());
    let off_mm = (last.0 - first.0).hypot(last.1 - first.1) * 1000.0;
    assert!(off_mm <= 50.0, "ended {off_mm:.1} mm from the dock");
}

/// A robot standing still maps one revolution a second, not ten
/// (`mission::locate`, `STILL_MAP_EVERY`). The 3790 home, unknown mode,
/// realistic noise, 1 person, seed 9: turning and waiting beside one wall
/// from 1,476 s, each revolution's match followed the map and each mapped
/// revolution moved the wall after the pose; both crept 60 mm in 10 s and
/// the rest of the home was mapped in that frame (pose RMS 40.4 mm against
/// the truth, maximum 65.7 mm). With the filter: 2.5 mm and 9.7 mm.
#[test]
fn a_robot_standing_still_does_not_drag_its_map_along() {
    let (rep, _) = unknown_home("3790", 9);
    assert!(
        rep.pose_error_rms_mm <= 30.0 && rep.pose_error_max_mm <= 100.0,
        "pose error RMS {:.1} mm, max {:.1} mm",
        rep.pose_error_rms_mm,
        rep.pose_error_max_mm
    );
}
