//! The robot image's map (unknown mode) is 12 × 12 m with the dock at its
//! centre, the map's axes the robot's at the dock. Measured on the six real
//! homes' truth: every home fits such a box when placed well, but with the
//! dock at the centre four of them reach past the map's edge.
//!
//! Placing the dock by what the lidar sees from it (the box seen, trimmed,
//! centred in the map) was tried and made it worse on four of the six:
//! the dock's room does not say where the rest of the home lies. So the
//! map scrolls as the robot explores (`robovac::mission::scroll`); the
//! missions here check that on the truth, in the robot's own frame
//! (`--dock-frame`).

use std::collections::VecDeque;

use host_sim::io::maps::parse_ascii;
use host_sim::run::mission::{docked_pose, run_mission, Capacity, MissionOptions, MissionReport};
use host_sim::run::suite::{suite_map, HOME_MAPS};
use host_sim::sim::robot::Noise;
use host_sim::sim::world::World;
use robovac::mission::MapMode;

/// The robot image's map side, m (`robovac::capacity::FW_HOME_SIDE` at
/// 5 cm).
const SIDE_M: f64 = robovac::capacity::FW_HOME_SIDE as f64 * 0.05;

/// World centres (m) of the floor cells reachable from `start`.
fn floor_from(world: &World, start: (f64, f64)) -> Vec<(f64, f64)> {
    let c = world.cell_m;
    let (w, h) = world.size_m();
    let (nx, ny) = ((w / c) as i32, (h / c) as i32);
    let at = |x: i32, y: i32| ((x as f64 + 0.5) * c, (y as f64 + 0.5) * c);
    let mut seen = vec![false; (nx * ny) as usize];
    let s = ((start.0 / c) as i32, (start.1 / c) as i32);
    let mut q = VecDeque::from([s]);
    seen[(s.1 * nx + s.0) as usize] = true;
    let mut out = Vec::new();
    while let Some((x, y)) = q.pop_front() {
        out.push(at(x, y));
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (a, b) = (x + dx, y + dy);
            if a < 0 || b < 0 || a >= nx || b >= ny || seen[(b * nx + a) as usize] {
                continue;
            }
            let (px, py) = at(a, b);
            if !world.blocked_at(px, py) {
                seen[(b * nx + a) as usize] = true;
                q.push_back((a, b));
            }
        }
    }
    out
}

/// Share of `floor` outside the map with the dock at `dock_mm` in it.
fn outside(floor: &[(f64, f64)], dock: (f64, f64), heading: f64, dock_mm: (i32, i32)) -> f64 {
    let (s, c) = heading.sin_cos();
    let (ax, ay) = (dock_mm.0 as f64 / 1000.0, dock_mm.1 as f64 / 1000.0);
    let out = floor
        .iter()
        .filter(|&&(x, y)| {
            let (dx, dy) = (x - dock.0, y - dock.1);
            let (rx, ry) = (ax + c * dx + s * dy, ay - s * dx + c * dy);
            !(0.0..SIDE_M).contains(&rx) || !(0.0..SIDE_M).contains(&ry)
        })
        .count();
    out as f64 / floor.len().max(1) as f64
}

#[test]
fn real_homes_fit_the_robot_images_map_but_not_centred_on_the_dock() {
    let side_mm = (SIDE_M * 1000.0) as i32;
    let mut lose = Vec::new();
    println!("home   floor m2   extent in the dock's frame   outside the map, dock centred");
    for (name, _) in HOME_MAPS {
        let map = suite_map(name).unwrap();
        let charger = map.dock.unwrap();
        let cell = map.cell_m.unwrap_or(0.05);
        let world = World::new(map, cell);
        let ((x, y), heading) = docked_pose(&world, charger, 0.165).unwrap();
        let floor = floor_from(&world, (x, y));
        let (s, c) = heading.sin_cos();
        let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
        for &(fx, fy) in &floor {
            let (dx, dy) = (fx - x, fy - y);
            let (rx, ry) = (c * dx + s * dy, -s * dx + c * dy);
            lo = (lo.0.min(rx), lo.1.min(ry));
            hi = (hi.0.max(rx), hi.1.max(ry));
        }
        let centred = outside(&floor, (x, y), heading, (side_mm / 2, side_mm / 2));
        println!(
            "{name:5} {:8.1}   {:4.1} x {:4.1} m (reach {:4.1} m)   {:5.1} %",
            floor.len() as f64 * cell * cell,
            hi.0 - lo.0,
            hi.1 - lo.1,
            [-lo.0, hi.0, -lo.1, hi.1].into_iter().fold(0.0, f64::max),
            100.0 * centred
        );
        // The target: every real home fits 12 × 12 m.
        assert!(hi.0 - lo.0 < SIDE_M && hi.1 - lo.1 < SIDE_M, "{name}");
        if centred > 0.0 {
            lose.push(name);
        }
    }
    // These would lose floor with the dock centred and the map fixed.
    assert_eq!(lose, ["z10", "S6", "3790", "l10su"]);
}

/// An 11 × 2.5 m room at 0.1 m cells (`maps/scroll/long_room.txt`).
fn long_room() -> host_sim::io::maps::MapData {
    let text = include_str!("../../maps/scroll/long_room.txt");
    parse_ascii(std::path::Path::new("long_room"), text.as_bytes()).unwrap()
}

/// The long room, unknown mode, at the firmware's capacity: in the
/// world's frame, or in the dock's (scrolling or not).
fn long_room_mission(dock_frame: bool, scroll: bool) -> MissionReport {
    let mut o = MissionOptions::new(long_room(), MapMode::Unknown, 0, Noise::None, 1);
    o.capacity = Capacity::Fw;
    o.dock_frame = dock_frame;
    o.scroll = scroll;
    o.start = Some((0.7, 1.5));
    o.start_heading = Some(0.0);
    o.max_time_s = 1500.0;
    run_mission(&o, |_, _, _| {}).unwrap().0
}

/// Docked at the west end of an 11 m room, the robot image's map (its
/// centre at the dock) ends 4.4 m short of the east wall. Fixed, it leaves
/// that part uncleaned; scrolling, the mission cleans the room as one on a
/// map of the whole world does, finishes at the dock, and its pose,
/// carried through every scroll, stays on the twin's true pose.
///
/// The dock stands 1.5 m from the south wall, a whole number of planning
/// cells, so the lanes lie as on the world's map. At 1.35 m (half a cell
/// off) both frames' lanes differ, and the dock's frame leaves an 8 cm
/// strip along the north wall that its top lane passes and the edge pass
/// takes as swept: 98.79 % against 99.90 %, scrolled or not (issue 12's
/// edge pass; the README's known limitations).
#[test]
fn the_map_scrolls_to_the_far_end_of_a_long_room() {
    let world = long_room_mission(false, true);
    let scrolled = long_room_mission(true, true);
    let fixed = long_room_mission(true, false);
    for (what, r) in [
        ("world", &world),
        ("scrolled", &scrolled),
        ("fixed", &fixed),
    ] {
        println!(
            "{what:8} coverage {:.2} % · {:.0} s · pose error max {:.0} mm · scrolls {:?} · {}",
            100.0 * r.coverage,
            r.cleaning_time_s,
            r.pose_error_max_mm,
            r.map_scrolls,
            r.final_state
        );
    }
    assert!(scrolled.map_scrolls.unwrap_or(0) >= 1);
    assert!(
        scrolled.finished && scrolled.docked,
        "{}",
        scrolled.final_state
    );
    assert_eq!(scrolled.collisions, 0);
    assert!(scrolled.coverage >= world.coverage - 0.01);
    assert!(scrolled.coverage > 0.97);
    assert!(scrolled.pose_error_max_mm < 100.0);
    assert_eq!(fixed.map_scrolls, Some(0));
    // About 4 of 11 m past the fixed map's edge (less the body's reach).
    assert!(fixed.coverage < 0.8, "{}", fixed.coverage);
}
