//! The bumper's marks in unknown mode: a person who walks into the robot
//! is marked like a table's crossbar the lidar cannot see, and those
//! marks can close a narrow place around the robot. Checked on the truth.

mod truth;

use host_sim::run::mission::{run_mission, MissionOptions};
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use robovac::mission::MapMode;
use truth::check_truth;

/// The home flat, unknown mode, 3 people, realistic noise, seed 11. At
/// 258 s a person walks into the robot's side in the 0.8 m wide pocket
/// at (5.9, 0.7) m; the bump is marked (3 cells), and from 376 s the
/// robot is boxed in on its map. Before the marks were forgotten the
/// edge pass restarted "boxed in" every 0.5 s for 150 s and the mission failed
/// with `NoWayHome` at 619 s, 18.5 % covered. Now the marks are forgotten
/// after 5 s boxed in (`EvidenceMap::forget_contacts`): the robot leaves,
/// cleans on and docks.
#[test]
fn marks_that_box_the_robot_in_are_forgotten() {
    let o = MissionOptions::new(
        suite_map("home").unwrap(),
        MapMode::Unknown,
        3,
        Noise::Realistic,
        11,
    );
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    assert!(rep.counters.bump_marks > 0, "{:?}", rep.counters);
    assert!(rep.finished && rep.docked, "{rep:?}");
    assert_eq!(rep.final_state, "Done", "{rep:?}");
    assert!(rep.coverage > 0.4, "coverage {:.4}", rep.coverage);
}
