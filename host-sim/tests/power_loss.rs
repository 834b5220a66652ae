//! A power loss mid-mission: the robot saved its map and which floor it
//! had cleaned every 60 s; after the reset it starts at its dock on the
//! saved map and cleans only what is left. Checked on the truth.

use host_sim::run::mission::MissionOptions;
use host_sim::run::power_loss::run_power_loss;
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use robovac::mission::MapMode;

/// A built-in flat on its prior map, realistic noise, nobody there.
fn flat(name: &str, seed: u64) -> MissionOptions {
    MissionOptions::new(
        suite_map(name).unwrap(),
        MapMode::Known,
        0,
        Noise::Realistic,
        seed,
    )
}

fn studio() -> MissionOptions {
    flat("studio", 2)
}

fn lanes_s(rep: &host_sim::run::mission::MissionReport) -> f64 {
    ["Cover", "Transit"]
        .iter()
        .map(|k| rep.state_time_s.get(*k).copied().unwrap_or(0.0))
        .sum()
}

#[test]
fn after_a_power_loss_in_the_lanes_only_the_rest_is_cleaned() {
    let pl = run_power_loss(&studio(), 300.0, 60.0, |_, _, _| {}).unwrap();
    let (first, second) = (&pl.first.0, &pl.second.0);
    let f = &pl.figures;
    assert!(!first.finished && first.coverage > 0.3, "{first:?}");
    assert!(second.finished && second.docked, "{second:?}");
    assert!(f.cells_restored >= 50, "{f:?}");
    assert!(f.coverage >= 0.97, "{f:?}");
    // The lanes already cleaned are not driven again: both runs' lanes
    // take about as long as the uninterrupted mission's.
    let (both, once) = (lanes_s(first) + lanes_s(second), lanes_s(&pl.uninterrupted));
    assert!(both < 1.25 * once, "{both} s of lanes against {once} s");
    assert_eq!(second.collisions, 0);
}

#[test]
fn a_power_loss_in_the_edge_pass_restores_its_progress_too() {
    // The edge pass runs from 429 s to 587 s of this mission (589-862 s
    // before the follower turned faster, issue 12; past 950 s before the
    // guard judged mapped hits by their wall points).
    let pl = run_power_loss(&studio(), 520.0, 60.0, |_, _, _| {}).unwrap();
    let (first, second) = (&pl.first.0, &pl.second.0);
    let edge = |r: &host_sim::run::mission::MissionReport| {
        r.state_time_s.get("Edge").copied().unwrap_or(0.0)
    };
    assert!(
        edge(first) > 0.0,
        "the cut came in the edge pass: {first:?}"
    );
    assert!(second.finished && second.docked, "{second:?}");
    assert!(pl.figures.coverage >= 0.97, "{:?}", pl.figures);
    // Contour cells restored besides the planning cells (all clean).
    let planning = first.floor_m2 / 0.09;
    assert!(
        pl.figures.cells_restored as f64 > planning,
        "{:?}",
        pl.figures
    );
    assert!(lanes_s(second) < 0.2 * lanes_s(first), "{second:?}");
}

/// The robot is put back on its dock after the reset as a person would:
/// here (home flat, realistic, seed 1) 90 mm and 60 mrad off. The rerun
/// matches its first revolution at the dock and maps it at the pose
/// found; it once mapped it at the pose it left, wiped the saved walls by
/// the dock, and never found itself again (failed lost at its start).
#[test]
fn a_rerun_put_down_off_its_dock_finds_itself_on_the_saved_map() {
    let pl = run_power_loss(&flat("home", 1), 450.0, 60.0, |_, _, _| {}).unwrap();
    let second = &pl.second.0;
    assert!(second.finished && second.docked, "{}", second.final_state);
    assert_eq!(second.collisions, 0);
    assert!(pl.figures.coverage >= 0.98, "{:?}", pl.figures);
    assert!(
        second.pose_error_max_mm <= 100.0,
        "{}",
        second.pose_error_max_mm
    );
}
