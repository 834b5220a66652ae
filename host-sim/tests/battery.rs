//! Recharge and resume on the twin's battery: a pack too small for the
//! home sends the robot to its dock to charge, again and again, and each
//! time it goes on where it stopped; the twin's battery (not the
//! executive's gauge reading) says it never ran flat.

use host_sim::run::mission::{run_mission, MissionOptions};
use host_sim::run::suite::suite_map;
use host_sim::sim::battery::REFERENCE;
use host_sim::sim::robot::Noise;
use robovac::mission::{EventKind, MapMode, State};

fn studio(battery_wh: f64) -> MissionOptions {
    let map = suite_map("studio").unwrap();
    let mut o = MissionOptions::new(map, MapMode::Known, 0, Noise::Realistic, 2);
    let mut spec = REFERENCE;
    spec.capacity_wh = battery_wh;
    o.battery = Some(spec);
    o
}

/// Resumed after a charge into `to`.
fn resumed_into(events: &[robovac::mission::Event], to: &[State]) -> usize {
    events
        .iter()
        .filter(|e| {
            matches!(e.kind, EventKind::State { from: State::Charging, to: t } if to.contains(&t))
        })
        .count()
}

#[test]
fn a_small_battery_charges_and_the_mission_goes_on() {
    // 2.3 Wh: the brisker follower (issue 12) cleans the studio on 4.8 Wh,
    // so a 3 Wh pack charged only once.
    let o = studio(2.3);
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    let b = rep.battery.clone().expect("the twin has a battery");
    assert!(rep.finished && rep.docked, "{rep:?}");
    assert!(rep.charges >= 2, "{rep:?}");
    assert!(!b.ran_flat && b.min_charge_pct >= 2.0, "{b:?}");
    assert!(rep.coverage >= 0.98, "{rep:?}");
    assert_eq!(rep.collisions, 0);
    // Both kinds of resume: into the lanes (or their transit) and into
    // the edge pass.
    let lanes = resumed_into(&t.events, &[State::Cover, State::Transit]);
    let edges = resumed_into(&t.events, &[State::Edge]);
    assert!(lanes >= 1 && edges >= 1, "lanes {lanes}, edges {edges}");
    assert_eq!(lanes + edges, rep.charges as usize);
    // Charging is time on the dock, apart from cleaning.
    assert!(rep.charging_time_s > 60.0 * rep.charges as f64, "{rep:?}");
    let sum = rep.cleaning_time_s + rep.charging_time_s;
    assert!((sum - rep.sim_time_s).abs() < 0.1, "{rep:?}");
    // It drew more than the pack holds: the charges were real.
    assert!(b.used_wh > 2.0 * b.capacity_wh, "{b:?}");
}

#[test]
fn with_the_charger_off_the_robot_fails_on_the_dock() {
    let mut o = studio(2.0);
    if let Some(b) = o.battery.as_mut() {
        b.charger_w = 0.0;
    }
    let (rep, _, _) = run_mission(&o, |_, _, _| {}).unwrap();
    assert_eq!(
        rep.final_state,
        format!("{:?}", State::Failed(robovac::mission::Fault::NotCharging))
    );
    assert!(rep.returned_to_start, "{rep:?}");
    assert!(rep.charging_time_s >= 600.0, "{rep:?}");
    assert!(!rep.battery.unwrap().ran_flat);
}

#[test]
fn without_a_gauge_the_time_budget_ends_the_mission() {
    let mut o = studio(3.0);
    o.battery = None;
    o.max_time_s = 900.0;
    let (rep, _, _) = run_mission(&o, |_, _, _| {}).unwrap();
    assert_eq!(rep.charges, 0);
    assert!(rep.battery.is_none());
    assert_eq!(rep.charging_time_s, 0.0);
    assert_eq!(rep.cleaning_time_s, rep.sim_time_s);
}
