//! Keeping the body off the walls beside it (`robovac::nav::keep_off`):
//! the nearest blocking cells against a brute-force scan, the integer
//! intrusions against a floating-point reference, and the steering's sign
//! and limits.

use proptest::prelude::*;
use robovac::nav::keep_off::{intrusions, steer, KeepOffParams, NearWalls, NEAR_CELLS};
use robovac::robot::lidar_map::{CellState, EvidenceMap};
use robovac::robot::odometry::Pose;

type Map = EvidenceMap<{ 64 * 64 }>;

const P: KeepOffParams = KeepOffParams {
    keep_mm: 8,
    gain_mrad_s_per_mm: 40,
    max_w_mrad_s: 600,
    slow_mm_s: 60,
};
const R: i32 = 165;

/// A free 64 × 64 map of 5 cm cells with `walls` (cell x, cell y) occupied.
fn map_with(walls: &[(i32, i32)]) -> Map {
    let mut map = Map::new();
    map.reset(64, 64, 50).unwrap();
    for y in 0..64 {
        for x in 0..64 {
            map.set_state(x, y, CellState::Free);
        }
    }
    for &(x, y) in walls {
        map.set_state(x, y, CellState::Occupied);
    }
    map
}

/// The world square (south-west corner, mm) of cell (cx, cy): rows count
/// down from the top of the map.
fn square_of(map: &Map, (cx, cy): (i32, i32)) -> (i32, i32) {
    let res = map.res_mm() as i32;
    (cx * res, (map.height() as i32 - 1 - cy) * res)
}

/// Distance (mm, f64) from point p to the square at corner c, side s.
fn dist_to_square(p: (f64, f64), c: (i32, i32), s: i32) -> f64 {
    let dx = (c.0 as f64 - p.0).max(0.0).max(p.0 - (c.0 + s) as f64);
    let dy = (c.1 as f64 - p.1).max(0.0).max(p.1 - (c.1 + s) as f64);
    dx.hypot(dy)
}

/// The intrusions in f64 with the same rule (side, not ahead, not behind
/// the middle) and exact distances, as bounds: a square within 1.5 mm of
/// the rule's edges (where the integer frame's rounding may decide
/// either way) counts only toward the upper bound. ((left lo, left hi),
/// (right lo, right hi)).
fn reference(walls: &NearWalls, pose: &Pose) -> ((f64, f64), (f64, f64)) {
    let (x0, y0) = (pose.x_mm as f64, pose.y_mm as f64);
    let th = pose.theta_mrad as f64 / 1000.0;
    let (mut left, mut right) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
    for (c, s) in walls.squares() {
        let q = (
            x0.clamp(c.0 as f64, (c.0 + s) as f64),
            y0.clamp(c.1 as f64, (c.1 + s) as f64),
        );
        let (dx, dy) = (q.0 - x0, q.1 - y0);
        let (fx, ly) = (dx * th.cos() + dy * th.sin(), dy * th.cos() - dx * th.sin());
        let counts = |e: f64| fx >= -(R / 2) as f64 - e && 2.0 * ly.abs() >= fx - 2.0 * e;
        let inside = (P.keep_mm as f64 - (dist_to_square((x0, y0), c, s) - R as f64)).max(0.0);
        let (sure, maybe) = (counts(-1.5), counts(1.5));
        for (side, on) in [(&mut left, ly > -1.5), (&mut right, ly < 1.5)] {
            if on && maybe {
                side.1 = side.1.max(inside);
            }
            if on && sure && ly.abs() >= 1.5 {
                side.0 = side.0.max(inside);
            }
        }
    }
    (left, right)
}

#[test]
fn a_wall_close_on_the_left_turns_the_robot_right_and_slows_it() {
    // A wall along row 20 (world y 2150..2200); the robot drives east
    // below it with its rim 3 mm from the wall.
    let walls: Vec<(i32, i32)> = (0..64).map(|x| (x, 43)).collect();
    let map = map_with(&walls);
    let wall_y = square_of(&map, (10, 43)).1;
    let pose = Pose {
        x_mm: 1000,
        y_mm: wall_y - R - 3,
        theta_mrad: 0,
    };
    let near = NearWalls::gather(&map, (pose.x_mm, pose.y_mm), R + 100);
    assert_eq!(intrusions(&P, &near, &pose, R), (5, 0));
    let (v, w) = steer(&P, &near, &pose, R, (300, 10));
    assert_eq!((v, w), (60, 10 - 5 * 40));
    // Backing up or turning in place: untouched.
    assert_eq!(steer(&P, &near, &pose, R, (-100, 0)), (-100, 0));
    assert_eq!(steer(&P, &near, &pose, R, (0, 500)), (0, 500));
    // 10 mm off (the plans' margin): no push.
    let clear = Pose {
        y_mm: wall_y - R - 10,
        ..pose
    };
    let near = NearWalls::gather(&map, (clear.x_mm, clear.y_mm), R + 100);
    assert_eq!(steer(&P, &near, &clear, R, (300, 10)), (300, 10));
}

#[test]
fn a_wall_ahead_is_left_to_the_guard_and_walls_on_both_sides_cancel() {
    // A wall across the way (column 30), the robot facing it, 2 mm away.
    let map = map_with(&(0..64).map(|y| (30, y)).collect::<Vec<_>>());
    let wall_x = square_of(&map, (30, 0)).0;
    let pose = Pose {
        x_mm: wall_x - R - 2,
        y_mm: 1600,
        theta_mrad: 0,
    };
    let near = NearWalls::gather(&map, (pose.x_mm, pose.y_mm), R + 100);
    assert_eq!(steer(&P, &near, &pose, R, (200, 0)), (200, 0));
    // A corridor 350 mm wide, the robot in the middle: 10 mm each side,
    // nothing to do.
    let corridor = |rows: (i32, i32)| {
        let mut walls: Vec<(i32, i32)> = (0..64).map(|x| (x, rows.0)).collect();
        walls.extend((0..64).map(|x| (x, rows.1)));
        let map = map_with(&walls);
        let top = square_of(&map, (0, rows.0)).1;
        let bottom = square_of(&map, (0, rows.1)).1 + 50;
        (map, top, bottom)
    };
    let (map, top, bottom) = corridor((20, 28));
    assert_eq!(top - bottom, 350, "corridor width");
    let mid = Pose {
        x_mm: 1500,
        y_mm: (top + bottom) / 2,
        theta_mrad: 0,
    };
    let near = NearWalls::gather(&map, (mid.x_mm, mid.y_mm), R + 100);
    assert_eq!(steer(&P, &near, &mid, R, (300, 0)), (300, 0));
    // 300 mm: 15 mm overlap each side (23 inside the keep); the pushes
    // cancel, the robot slows.
    let (map, top, bottom) = corridor((20, 27));
    assert_eq!(top - bottom, 300);
    let mid = Pose {
        y_mm: (top + bottom) / 2,
        ..mid
    };
    let near = NearWalls::gather(&map, (mid.x_mm, mid.y_mm), R + 100);
    assert_eq!(intrusions(&P, &near, &mid, R), (23, 23));
    assert_eq!(steer(&P, &near, &mid, R, (300, 0)), (60, 0));
}

#[test]
fn gather_keeps_the_nearest_cells_nearest_first() {
    let walls = [(10, 10), (12, 10), (14, 10), (16, 10), (18, 10), (20, 10)];
    let map = map_with(&walls);
    let here = (
        square_of(&map, (10, 10)).0 + 25,
        square_of(&map, (10, 12)).1,
    );
    let near = NearWalls::gather(&map, here, 2000);
    let got: Vec<(i32, i32)> = near.squares().map(|(c, _)| c).collect();
    let want: Vec<(i32, i32)> = walls[..NEAR_CELLS]
        .iter()
        .map(|&c| square_of(&map, c))
        .collect();
    assert_eq!(got, want);
    // Beyond the reach: nothing.
    assert_eq!(NearWalls::gather(&map, here, 10).squares().count(), 0);
}

/// Cases with a wall inside the keep (the property is not vacuous).
static HITS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    /// On random clutter and poses (the reach inside the map: off it,
    /// every cell blocks), the nearest cells are those a brute
    /// force finds, and the integer intrusions are within 1 mm of the
    /// floating-point ones.
    #[test]
    fn gather_and_intrusions_match_a_reference(
        offsets in proptest::collection::vec((-6i32..=6, -6i32..=6), 0..30),
        x in 500i32..2700,
        y in 500i32..2700,
        th in -3141i32..3141,
    ) {
        // Clutter around the pose's cell, so most cases have walls near.
        let (px, py) = (x / 50, 63 - y / 50);
        let mut cells: Vec<(i32, i32)> = offsets.iter().map(|&(dx, dy)| (px + dx, py + dy)).collect();
        cells.sort();
        cells.dedup();
        let map = map_with(&cells);
        let reach = R + P.keep_mm + 100;
        let near = NearWalls::gather(&map, (x, y), reach);
        let mut all: Vec<f64> = cells
            .iter()
            .map(|&c| dist_to_square((x as f64, y as f64), square_of(&map, c), 50))
            .filter(|&d| d <= reach as f64)
            .collect();
        all.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let got: Vec<f64> = near
            .squares()
            .map(|(c, s)| dist_to_square((x as f64, y as f64), c, s))
            .collect();
        prop_assert!(got.len() <= NEAR_CELLS);
        prop_assert!(got.windows(2).all(|w| w[0] <= w[1] + 1e-9), "nearest first: {:?}", got);
        // The k nearest distances agree with the brute force's.
        for (g, w) in got.iter().zip(all.iter()) {
            prop_assert!((g - w).abs() < 1e-9, "{:?} vs {:?}", got, all);
        }
        let pose = Pose { x_mm: x, y_mm: y, theta_mrad: th };
        let (l, r) = intrusions(&P, &near, &pose, R);
        let (fl, fr) = reference(&near, &pose);
        let within = |v: i32, (lo, hi): (f64, f64)| v as f64 >= lo - 1.0 && v as f64 <= hi + 1.0;
        prop_assert!(within(l, fl) && within(r, fr), "int ({l}, {r}) vs f64 {fl:?} {fr:?}");
        HITS.fetch_add(usize::from(l + r > 0), std::sync::atomic::Ordering::Relaxed);
    }
}

#[test]
fn the_random_cases_put_walls_inside_the_keep() {
    gather_and_intrusions_match_a_reference();
    let n = HITS.load(std::sync::atomic::Ordering::Relaxed);
    assert!(n >= 40, "only {n} of 400 cases had a wall within the keep");
}

/// The distance (mm, f64) a disc of radius `r` at `p` moving along
/// heading `th` travels before touching the square (corner `c`, side
/// `s`): brute force over the outline at 0.05 mm; `None` if never.
fn first_contact(p: (f64, f64), th: f64, r: f64, c: (i32, i32), s: i32) -> Option<f64> {
    let (c0, c1, s) = (c.0 as f64, c.1 as f64, s as f64);
    let mut best: Option<f64> = None;
    for i in 0..=(s * 20.0) as i32 {
        let t = i as f64 / 20.0;
        for q in [
            (c0 + t, c1),
            (c0 + t, c1 + s),
            (c0, c1 + t),
            (c0 + s, c1 + t),
        ] {
            let (dx, dy) = (q.0 - p.0, q.1 - p.1);
            let (fx, ly) = (dx * th.cos() + dy * th.sin(), dy * th.cos() - dx * th.sin());
            if ly.abs() < r && fx > 0.0 {
                let d = (fx - (r * r - ly * ly).sqrt()).max(0.0);
                best = Some(best.map_or(d, |b: f64| b.min(d)));
            }
        }
    }
    best
}

proptest! {
    /// The guard's outline points of one blocking cell (the nearest
    /// counts) give a free distance between the first contacts of discs
    /// 1 mm narrower and 1 mm wider than the body (±1 mm; the integer
    /// frame's rounding): the guard stops a body heading for a corner no
    /// beam struck, and does not stop one passing it.
    #[test]
    fn outline_points_bound_the_first_contact(
        d in 166.0f64..450.0, a in -std::f64::consts::PI..std::f64::consts::PI, th in -3141i32..3141,
    ) {
        let map = map_with(&[(30, 30)]);
        let c = square_of(&map, (30, 30));
        let here = (c.0 + 25 + (d * a.cos()) as i32, c.1 + 25 + (d * a.sin()) as i32);
        // A body already on the cell is the escape's, not the guard's.
        prop_assume!(dist_to_square((here.0 as f64, here.1 as f64), c, 50) > R as f64);
        let near = NearWalls::gather(&map, here, 1000);
        let pose = Pose { x_mm: here.0, y_mm: here.1, theta_mrad: th };
        let frame = robovac::nav::geometry::RobotFrame::of(&pose);
        let mut f = robovac::nav::guard::FreeDistance::new(R, true);
        for q in near.outline_points() {
            f.push(frame.to_robot(q));
        }
        let got = f.nearest();
        let p = (here.0 as f64, here.1 as f64);
        match first_contact(p, th as f64 / 1000.0, R as f64, c, 50) {
            Some(want) => {
                // The integer frame rounds a point ±0.5 mm across the
                // corridor, where the half chord is steep: bounded by a
                // disc 1 mm narrower.
                let narrower = first_contact(p, th as f64 / 1000.0, R as f64 - 1.0, c, 50);
                let most = narrower.unwrap_or(f64::MAX) + 1.0;
                prop_assert!(got as f64 <= most, "got {got}, want {want}");
                let wider = first_contact(p, th as f64 / 1000.0, R as f64 + 1.0, c, 50);
                let least = wider.unwrap_or(0.0) - 1.0;
                prop_assert!(got as f64 >= least, "got {got}, want {want}");
            }
            // Rounding may take in a corner a hair outside the corridor.
            None => prop_assert!(
                got == i32::MAX || first_contact(p, th as f64 / 1000.0, R as f64 + 1.5, c, 50).is_some(),
                "got {got}, no contact"
            ),
        }
    }
}

proptest! {
    /// `outline_points_beside` leaves out exactly the squares nearer than
    /// `under` to `here` (against the f64 distance; cases with a square
    /// within 1 mm of the edge are skipped) and keeps the others'
    /// outlines whole.
    #[test]
    fn outline_points_beside_leave_out_the_squares_under_the_body(
        cells in proptest::collection::vec((20i32..44, 20i32..44), 1..6),
        dx in -400i32..400, dy in -400i32..400, under in 0i64..200,
    ) {
        let map = map_with(&cells);
        let here = (1600 + dx, 1600 + dy);
        let near = NearWalls::gather(&map, here, 1000);
        let per_square = near.outline_points().count() / near.squares().count().max(1);
        let kept: Vec<_> = near.outline_points_beside(here, under).collect();
        let mut want = 0;
        for (c, s) in near.squares() {
            let d = dist_to_square((here.0 as f64, here.1 as f64), c, s);
            prop_assume!((d - under as f64).abs() > 1.0);
            if d > under as f64 {
                want += per_square;
                let (x1, y1) = (c.0 + s, c.1 + s);
                for q in [c, (x1, c.1), (x1, y1), (c.0, y1)] {
                    prop_assert!(kept.contains(&q), "square {c:?} at {d:.1} mm lost {q:?}");
                }
            }
        }
        prop_assert_eq!(kept.len(), want, "under {}", under);
    }
}
