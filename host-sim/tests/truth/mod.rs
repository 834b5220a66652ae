//! The mission tests' checks on the ground truth, written once: the true
//! trajectory never puts the body over a wall, its length matches the
//! distance the executive reports, and the robot moved into nothing.
#![allow(dead_code)]

use host_sim::run::mission::{MissionOptions, MissionReport, MissionTrace};
use host_sim::sim::robot::RobotConfig;
use host_sim::sim::world::World;

/// The body (the twin's true disc) never overlaps a wall of the map.
pub fn body_never_over_a_wall(o: &MissionOptions, t: &MissionTrace) {
    let world = World::new(o.map.clone(), o.cell_m);
    let r = RobotConfig::default().diameter_m / 2.0;
    for &(x, y) in &t.truth {
        assert!(
            !world.disc_hits_wall(x, y, r - 1e-6),
            "the body overlaps a wall at ({x:.3}, {y:.3})"
        );
    }
}

/// Independent checks on the truth: the body never over a wall, the
/// distance reported is the true trajectory's, no collision.
pub fn check_truth(o: &MissionOptions, rep: &MissionReport, t: &MissionTrace) {
    body_never_over_a_wall(o, t);
    let len: f64 = t
        .truth
        .windows(2)
        .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
        .sum();
    assert!(
        (len - rep.distance_m).abs() < 0.01 * rep.distance_m + 0.05,
        "trajectory {len:.2} m vs reported {:.2} m",
        rep.distance_m
    );
    assert_eq!(rep.collisions, 0, "the robot moved into something");
}
