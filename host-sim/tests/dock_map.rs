//! The robot image's map (unknown mode) is 12 × 12 m with the dock at its
//! centre, the map's axes the robot's at the dock. Measured on the six real
//! homes' truth: every home fits such a box when placed well, but with the
//! dock at the centre four of them lose floor past the map's edge.
//!
//! Placing the dock by what the lidar sees from it (the box seen, trimmed,
//! centred in the map) was tried and made it worse on four of the six:
//! the dock's room does not say where the rest of the home lies. A map
//! that scrolls as the robot explores is the fix.

use std::collections::VecDeque;

use host_sim::run::mission::docked_pose;
use host_sim::run::suite::{suite_map, HOME_MAPS};
use host_sim::sim::world::World;

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
    // The known limitation (README): these lose floor with the dock centred.
    assert_eq!(lose, ["z10", "S6", "3790", "l10su"]);
}
