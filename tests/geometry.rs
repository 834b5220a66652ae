//! Integer geometry: square roots, distances, the OHA* weight, the
//! supercover line and the grid's edges.

mod common;

use common::*;
use proptest::prelude::*;
use robovac::grid::los::{line_of_sight, supercover};
use robovac::grid::{GridError, Layer};
use robovac::math::cost::{
    euclid, isqrt_round_u64, isqrt_u64, octile, COST_DIAGONAL, COST_PER_CELL,
};
use robovac::search::heuristics::weighted;
use robovac::{Cell, Grid};

#[test]
fn cost_constants_approximate_sqrt2() {
    let r = COST_DIAGONAL as f64 / COST_PER_CELL as f64;
    assert!((r - std::f64::consts::SQRT_2).abs() < 2e-8);
    assert_eq!(euclid(1, 1), COST_DIAGONAL);
    assert_eq!(euclid(1, 0), COST_PER_CELL);
    assert_eq!(octile(3, -5), 3 * COST_DIAGONAL + 2 * COST_PER_CELL);
}

proptest! {
    #[test]
    fn isqrt_is_exact(n in any::<u64>()) {
        let r = isqrt_u64(n) as u128;
        prop_assert!(r * r <= n as u128 && (r + 1) * (r + 1) > n as u128);
        let rr = isqrt_round_u64(n) as f64;
        prop_assert!((rr - (n as f64).sqrt()).abs() <= 0.5 + 1e-6 * (n as f64).sqrt().max(1.0) * 1e-6);
    }

    /// The fast roots (Newton on 32 bits, one refining step on 64) against
    /// the definition, where they are most likely to be off by one: at and
    /// around perfect squares, small numbers, and the top of each range.
    #[test]
    fn isqrt_is_exact_around_squares(s in any::<u32>(), d in -3i64..=3, small in any::<u32>()) {
        let n = (s as i128 * s as i128 + d as i128).clamp(0, u64::MAX as i128) as u64;
        for n in [n, n >> 20, small as u64, u64::MAX - (small as u64), u32::MAX as u64 - (small as u64 >> 8)] {
            let r = isqrt_u64(n) as u128;
            prop_assert!(r * r <= n as u128 && (r + 1) * (r + 1) > n as u128, "isqrt_u64({n}) = {r}");
        }
        let r = robovac::math::cost::isqrt_u32(small) as u64;
        prop_assert!(r * r <= small as u64 && (r + 1) * (r + 1) > small as u64, "isqrt_u32({small}) = {r}");
    }

    /// CORDIC atan2 is within 1 µrad of f64 over the whole circle, and a
    /// reversal is +π.
    #[test]
    fn atan2_matches_f64(y in -1_000_000i64..1_000_000, x in -1_000_000i64..1_000_000) {
        prop_assume!((x, y) != (0, 0));
        let ours = robovac::math::angle::atan2_urad(y, x) as f64;
        let exact = (y as f64).atan2(x as f64) * 1e6;
        prop_assert!((ours - exact).abs() <= 1.0, "atan2({y},{x}) = {ours} vs {exact}");
        prop_assert!((robovac::math::angle::atan2_mrad(y as i32, x as i32) as f64 - exact / 1000.0).abs() <= 0.51);
    }

    #[test]
    fn euclid_within_half_a_unit(dx in -2000i32..2000, dy in -2000i32..2000) {
        let exact = ((dx as f64).powi(2) + (dy as f64).powi(2)).sqrt() * COST_PER_CELL as f64;
        prop_assert!((euclid(dx, dy) as f64 - exact).abs() <= 0.5 + 1e-6);
    }

    /// The integer OHA* heuristic matches the float formula (2 + cos θ)·h to
    /// within 3 cost units plus 10⁻⁶ relative (under 0.001 cells on a
    /// 1000-cell distance) and stays in [h, 3h].
    #[test]
    fn oha_weight_matches_float(s in (0u16..200, 0u16..200), a in (0u16..200, 0u16..200), b in (0u16..200, 0u16..200)) {
        let (s, start, goal) = (Cell::new(s.0, s.1), Cell::new(a.0, a.1), Cell::new(b.0, b.1));
        let hp = weighted(s, start, goal) as f64;
        let v = |c: Cell| (c.x as f64 - s.x as f64, c.y as f64 - s.y as f64);
        let (ax, ay) = v(goal);
        let (bx, by) = v(start);
        let h = (ax * ax + ay * ay).sqrt() * COST_PER_CELL as f64;
        let expect = if s == start || s == goal {
            h
        } else {
            let cos = (ax * bx + ay * by) / ((ax * ax + ay * ay).sqrt() * (bx * bx + by * by).sqrt());
            (2.0 + cos) * h
        };
        prop_assert!((hp - expect).abs() <= 3.0 + 1e-6 * expect, "h' {hp} vs {expect}");
        prop_assert!(hp >= h - 1.0 && hp <= 3.0 * h + 1.0);
    }

    /// The supercover walk is symmetric, connected, and touches exactly the
    /// cells an independent dense sampling finds.
    #[test]
    fn supercover_is_conservative(ax in 0i32..30, ay in 0i32..30, bx in 0i32..30, by in 0i32..30) {
        let mut fwd = Vec::new();
        supercover((ax, ay), (bx, by), |x, y| { fwd.push((x, y)); true });
        let mut back = Vec::new();
        supercover((bx, by), (ax, ay), |x, y| { back.push((x, y)); true });
        prop_assert_eq!(fwd.first().copied(), Some((ax, ay)));
        prop_assert_eq!(fwd.last().copied(), Some((bx, by)));
        let mut f2 = fwd.clone(); f2.sort(); f2.dedup();
        let mut b2 = back.clone(); b2.sort(); b2.dedup();
        prop_assert_eq!(&f2, &b2);
        // compare with the exact oracle on maps where one cell is blocked
        for &(cx, cy) in &[(ax, ay), ((ax + bx) / 2, (ay + by) / 2), ((ax + bx) / 2 + 1, (ay + by) / 2)] {
            let mut g = TGrid::new();
            g.reset(32, 32).unwrap();
            if (cx, cy) == (ax, ay) || (cx, cy) == (bx, by) { continue; }
            g.set_obstacle(cx, cy, true).unwrap();
            let a = Cell::new(ax as u16, ay as u16);
            let b = Cell::new(bx as u16, by as u16);
            prop_assert_eq!(line_of_sight(&g, a, b), segment_clear(&g, a, b), "cell ({},{})", cx, cy);
        }
    }
}

#[test]
fn atan2_reversal_is_plus_pi() {
    assert_eq!(robovac::math::angle::atan2_urad(0, -5), 3_141_593);
    assert_eq!(robovac::math::angle::atan2_urad(0, -1_000_000), 3_141_593);
    assert_eq!(robovac::math::angle::atan2_urad(0, 0), 0);
}

#[test]
fn diagonal_line_of_sight_needs_both_sides() {
    let mut g = TGrid::new();
    g.load_ascii("..\n#.\n").unwrap();
    assert!(!line_of_sight(&g, Cell::new(0, 0), Cell::new(1, 1)));
    g.load_ascii("..\n..\n").unwrap();
    assert!(line_of_sight(&g, Cell::new(0, 0), Cell::new(1, 1)));
}

#[test]
fn grid_edges_never_panic() {
    let mut g: Grid<4> = Grid::new();
    assert!(g.is_blocked(0, 0), "empty grid reads blocked");
    assert_eq!(g.reset(0, 5), Err(GridError::Empty));
    assert!(matches!(g.reset(12, 11), Err(GridError::TooLarge { .. })));
    g.reset(16, 8).unwrap();
    assert_eq!(g.cells(), 128);
    for (x, y) in [(-1, 0), (0, -1), (16, 0), (0, 8), (i32::MIN, i32::MAX)] {
        assert!(g.is_blocked(x, y));
        assert!(!g.get(Layer::Covered, x, y));
        assert_eq!(g.set_obstacle(x, y, true), Err(GridError::OffMap { x, y }));
    }
    g.set(Layer::Covered, 15, 7, true).unwrap();
    assert!(g.get(Layer::Covered, 15, 7));
    assert_eq!(g.count(Layer::Covered), 1);
    assert_eq!(g.free_cells(), 128);
    assert_eq!(
        g.load_ascii("..\n...\n"),
        Err(GridError::RaggedRows { row: 1 })
    );
    assert_eq!(
        g.load_ascii("..\n.x\n"),
        Err(GridError::BadChar { row: 1, col: 1 })
    );
}

#[test]
fn memory_sizes() {
    use robovac::capacity::*;
    // The compile-time assertions live in src/capacity.rs; this prints them.
    println!("search state 128x128: {SEARCH128_BYTES} bytes; grid 128x128: {GRID128_BYTES} bytes; firmware search: {FW_SEARCH_BYTES} bytes");
    // 8 bytes a cell + 2 bits a cell + 12 bytes an open entry, + fixed part.
    assert_eq!(search_state_bytes(REF128_CELLS, REF128_OPEN), 184_320);
}

proptest! {
    /// smallest_k agrees with sorting (stable) and truncating.
    #[test]
    fn smallest_k_is_a_stable_partial_sort(v in prop::collection::vec(-50i64..50, 0..40), k in 0usize..12) {
        let mut out = vec![0i64; k];
        let n = robovac::math::select::smallest_k(&v, &mut out, |x| *x);
        let mut sorted = v.clone();
        sorted.sort();
        sorted.truncate(k);
        prop_assert_eq!(&out[..n], &sorted[..]);
    }
}
