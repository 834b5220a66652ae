//! The F405/F407's capacity, 16 × 16 m (`robovac::capacity::home16`,
//! issue 11 §3), on the host: missions in exactly the buffers that image
//! has (`--capacity fw16`), checked on the truth.

mod truth;

use host_sim::run::mission::{run_mission, Capacity, MissionOptions};
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use robovac::mission::MapMode;
use truth::check_truth;

/// The 15.6 × 15.6 m house drawn for this capacity (`maps/flat/house.txt`,
/// 210 m² of floor).
fn house() -> host_sim::io::maps::MapData {
    let text = include_str!("../../maps/flat/house.txt");
    let mut m = host_sim::io::maps::parse_ascii(std::path::Path::new("house"), text.as_bytes())
        .expect("the house parses");
    m.cell_m = Some(0.1);
    m
}

/// A whole mission in the 16 m buffers cleans the home flat as the 12 m
/// ones do, and comes back.
#[test]
fn the_16_m_capacity_cleans_the_home_flat() {
    let map = suite_map("home").unwrap();
    let mut o = MissionOptions::new(map, MapMode::Known, 0, Noise::None, 1);
    o.capacity = Capacity::Fw16;
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    assert!(rep.finished && rep.returned_to_start, "{rep:?}");
    assert!(rep.coverage >= 0.97, "coverage {:.4}", rep.coverage);
}

/// A home past 12 m is refused by the F411's buffers with a one-line
/// reason, and taken by the F405/F407's: the robot cleans in it, on the
/// truth without a collision, and its map and plans span the whole house.
#[test]
fn a_house_past_12_m_takes_the_16_m_capacity() {
    let mut o = MissionOptions::new(house(), MapMode::Known, 0, Noise::None, 1);
    o.capacity = Capacity::Fw;
    let err = run_mission(&o, |_, _, _| {})
        .err()
        .expect("refused at 12 m");
    assert!(err.contains("exceeds the capacity"), "{err}");
    assert!(!err.contains('\n'), "{err}");
    o.capacity = Capacity::Fw16;
    o.max_time_s = 300.0;
    let (rep, t, _) = run_mission(&o, |_, _, _| {}).unwrap();
    check_truth(&o, &rep, &t);
    assert_eq!(rep.collisions, 0);
    // 300 s of lanes at 0.3 m/s and 0.33 m: at most about 30 m²; the first
    // room and a half are swept.
    assert!(
        rep.coverage * rep.floor_m2 > 15.0,
        "{:.1} m²",
        rep.coverage * rep.floor_m2
    );
}
