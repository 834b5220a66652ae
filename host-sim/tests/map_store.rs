//! The map kept between runs (issue 12): the saved image on the robot's
//! store (`robovac::robot::map_image`), its checks, and two missions on
//! the twin, the second on the map the first saved.

mod truth;

use host_sim::io::store::MemStore;
use host_sim::run::mission::{run_mission, MapStore, MissionOptions};
use host_sim::run::suite::suite_map;
use host_sim::sim::robot::Noise;
use robovac::mission::MapMode;
use robovac::robot::hal::Storage;
use robovac::robot::lidar_map::{CellState, EvidenceMap};
use robovac::robot::map_image::{load, save, MapImageError, HEADER_BYTES};
use robovac::robot::odometry::Pose;

type Map = EvidenceMap<{ 64 * 64 }>;

const DOCK: Pose = Pose {
    x_mm: 1234,
    y_mm: -56,
    theta_mrad: -3000,
};

/// A 37 × 29 map (an odd cell count) of every evidence value.
fn sample_map() -> Box<Map> {
    let mut m = Box::new(Map::new());
    m.reset(37, 29, 50).unwrap();
    for y in 0..29 {
        for x in 0..37 {
            let st = [CellState::Occupied, CellState::Free, CellState::Unknown][(x * 7 + y) % 3];
            m.set_state(x as i32, y as i32, st);
        }
    }
    for k in 0..40 {
        m.trace(25, 25 + 30 * k, 1800, 1400 - 20 * k, k % 2 == 0);
    }
    m.mark_contact(700, 700);
    m
}

#[test]
fn a_saved_map_loads_as_it_was() {
    let m = sample_map();
    let mut store = MemStore::erased();
    let n = save(&*m, DOCK, &mut store).unwrap();
    assert_eq!(n, HEADER_BYTES + (37 * 29_u32).div_ceil(2));
    assert_eq!(store.written().len(), n as usize);
    let mut back = Box::new(Map::new());
    assert_eq!(load(&mut store, &mut *back), Ok(DOCK));
    assert_eq!((back.width(), back.height(), back.res_mm()), (37, 29, 50));
    // Walls are kept; weak or lone hits come back unknown.
    let strong = |x: i32, y: i32| m.evidence(x, y) >= 6;
    let (mut walls, mut dropped) = (0, 0);
    for y in 0..29 {
        for x in 0..37 {
            let e = m.evidence(x, y);
            let around = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                .filter(|&(dx, dy)| (dx, dy) != (0, 0) && strong(x + dx, y + dy))
                .count();
            let lone = e >= 2 && e != 7 && !(e >= 6 && around >= 2);
            let want = if lone { 0 } else { e };
            (walls, dropped) = (walls + (e >= 2 && !lone) as u32, dropped + lone as u32);
            assert_eq!(back.evidence(x, y), want, "({x}, {y}): {e}");
        }
    }
    assert!(
        walls > 50 && dropped > 5,
        "{walls} walls kept, {dropped} dropped"
    );
}

#[test]
fn a_damaged_or_missing_map_is_refused_whole() {
    let m = sample_map();
    let mut good = MemStore::erased();
    save(&*m, DOCK, &mut good).unwrap();
    let refused = |store: &mut MemStore| {
        let mut back = Box::new(Map::new());
        back.reset(5, 5, 50).unwrap();
        let r = load(store, &mut *back);
        assert_eq!((back.width(), back.height()), (0, 0), "left empty");
        r.unwrap_err()
    };
    assert_eq!(refused(&mut MemStore::erased()), MapImageError::NoMap);
    // One flipped bit anywhere in the cells or the header.
    for at in [40usize, 300, 12, 26] {
        let mut s = good.clone();
        s.bytes_mut()[at] ^= 0x10;
        assert_eq!(refused(&mut s), MapImageError::Corrupt, "byte {at}");
    }
    let mut s = good.clone();
    s.bytes_mut()[4] = 9;
    assert_eq!(refused(&mut s), MapImageError::Version { found: 9 });
    // A save cut short by a power loss: the cells written, the header not.
    let mut s = MemStore::erased();
    s.write(HEADER_BYTES, &good.written()[HEADER_BYTES as usize..])
        .unwrap();
    assert_eq!(refused(&mut s), MapImageError::NoMap);
    // A map larger than the store (a 600 × 500 building at 5 cm).
    let mut big = Box::new(EvidenceMap::<150_000>::new());
    big.reset(600, 500, 50).unwrap();
    assert!(matches!(
        save(&*big, DOCK, &mut MemStore::erased()),
        Err(MapImageError::TooLarge { .. })
    ));
}

fn opts(map: &str, noise: Noise, seed: u64) -> MissionOptions {
    let mut o = MissionOptions::new(suite_map(map).unwrap(), MapMode::Unknown, 1, noise, seed);
    o.map_store.save = true;
    o
}

/// The first run explores the studio and saves its map; the second starts
/// from it, put down off the dock by up to ±0.2 m and ±15°: it
/// relocalises there, cleans and docks, checked on the truth. A map saved
/// in one home is refused in another.
#[test]
fn the_second_run_starts_from_the_map_the_first_saved() {
    let first = opts("studio", Noise::Realistic, 1);
    let (rep1, t1, _) = run_mission(&first, |_, _, _| {}).unwrap();
    assert!(rep1.finished && rep1.docked);
    let (store, bytes) = t1.saved_map.expect("the finished run saved its map");
    assert!(bytes > HEADER_BYTES);
    let mut second = opts("studio", Noise::Realistic, 2);
    second.map_store = MapStore {
        load: Some(store.clone()),
        save: false,
        ..Default::default()
    };
    let (rep2, t2, _) = run_mission(&second, |_, _, _| {}).unwrap();
    let moved = t2.events.iter().find_map(|e| match e.kind {
        robovac::mission::EventKind::Relocalised { moved_mm, .. } => Some(moved_mm),
        _ => None,
    });
    assert!(
        moved.is_some_and(|m| m > 20),
        "relocalised at the dock: {moved:?}"
    );
    assert!(rep2.finished && rep2.docked, "{}", rep2.final_state);
    assert!(rep2.coverage >= 0.95, "coverage {}", rep2.coverage);
    assert!(
        rep2.pose_error_max_mm <= 100.0,
        "{}",
        rep2.pose_error_max_mm
    );
    truth::body_never_over_a_wall(&second, &t2);
    let mut elsewhere = opts("home", Noise::None, 1);
    elsewhere.map_store.load = Some(store);
    let Err(err) = run_mission(&elsewhere, |_, _, _| {}) else {
        panic!("a map of the studio was taken in the home flat");
    };
    assert!(err.contains("not of this home"), "{err}");
}
