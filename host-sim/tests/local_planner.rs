//! The potential field steering the mission's avoidances in place of DWA
//! (issue 13: "the artificial potential field as a local planner next to
//! DWA, with its local minima shown, not hidden"). Checked on the twin's
//! truth: no collision, the body never over a wall, the floor cleaned and
//! the robot docked; and every local minimum the executive counts is in
//! its events, where the robot truly was.

mod cli_common;
mod truth;

use cli_common::assert_refused;
use host_sim::run::mission::{run_mission, MissionOptions};
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use robovac::mission::{EventKind, LocalPlanner, MapMode};

#[test]
fn the_potential_field_steers_the_home_flat_and_shows_its_local_minima() {
    // Two people and realistic noise: this run meets one local minimum
    // (measured; the count is the executive's, checked against its events).
    // Seed 9. Earlier seeds stopped meeting one as the executive changed:
    // seed 1 when given-up lanes were handed back whatever stands on them,
    // seed 7 when the robot kept off the walls beside it (`nav::keep_off`),
    // seed 16 when its edge pass grazed a door jamb, seed 11 when the
    // edge pass began to drive the contours it plans, and seed 3 when the
    // guard began to judge mapped hits by the wall points they stand for
    // (issue 10), seed 4 when transits kept farther off the walls
    // (`keep_off_transit`), seed 2 when people's legs became at least
    // 1 m long (`sim::world::MIN_LEG_M`), seed 1 when their loops had
    // 3 waypoints at least (`sim::world::MIN_LOOP`), seed 3 when the
    // guard counted the nearest map cells (`Mission::cells_free`), seed 4
    // when known mode's lidar hits stood only for fixed walls
    // (`wall_offset`'s `fixed_only`), seed 8 when the guard left out the
    // map cells under the body (`UNDER_BODY_MM`), seed 9 when the
    // follower turned faster and braked harder (issue 12's time). Seeds
    // 1-16 tried: only 9 meets one, every run docked with no collision.
    let map = suite_map("home").unwrap();
    let mut o = MissionOptions::new(map, MapMode::Known, 2, Noise::Realistic, 9);
    o.local = LocalPlanner::Apf;
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    truth::check_truth(&o, &rep, &t);
    assert!(rep.finished && rep.returned_to_start, "{rep:?}");
    assert!(rep.coverage >= 0.97, "coverage {:.4}", rep.coverage);
    assert!(rep.avoidance_events > 0);
    let minima: Vec<(f64, f64)> = t
        .events
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::LocalMinimum { x_mm, y_mm } => Some((x_mm as f64 / 1e3, y_mm as f64 / 1e3)),
            _ => None,
        })
        .collect();
    assert!(!minima.is_empty(), "this run meets a local minimum");
    assert_eq!(minima.len() as u32, rep.counters.apf_minima);
    for m in minima {
        let near = t
            .truth
            .iter()
            .map(|p| (p.0 - m.0).hypot(p.1 - m.1))
            .fold(f64::MAX, f64::min);
        assert!(
            near < 0.3,
            "a minimum at {m:?} is {near:.2} m from the true path"
        );
    }
}

#[test]
fn dwa_stays_the_default_and_the_flag_is_checked() {
    let map = suite_map("studio").unwrap();
    let o = MissionOptions::new(map, MapMode::Known, 0, Noise::None, 1);
    assert_eq!(o.local, LocalPlanner::Dwa);
    assert_refused(&[
        "mission",
        "--map",
        "maps/flat/studio.txt",
        "--local",
        "nope",
    ]);
}
