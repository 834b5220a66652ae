//! The heuristics of the search loop ([`super::run`]): the Euclidean
//! distance of A* and Theta* (Hart, Nilsson and Raphael 1968; ALGORITHMS.md
//! §5 and seed 000 eq. 1), and OHA*'s orientation-weighted one (seed 000
//! §2.3, eq. 2).
//!
//! **A\*.** f(s) = g(s) + h(s) with h the **Euclidean** distance to the
//! nearest goal: seed 000 calls this the "traditional A*" it compares OHA*
//! against. The Euclidean distance never exceeds the octile distance, so h
//! is admissible and consistent on the 8-connected grid and the path cost
//! is optimal.
//!
//! **OHA\*.** h'(s) = (2 + cos θ)·h(s), θ ∈ [0, π] the angle at `s` between the
//! vectors s→goal and s→start, and cos θ = −1 (h' = h) when `s` is the
//! start or the goal. h is the Euclidean distance. Cells on the start–goal
//! segment keep weight 1, cells off to the side get up to 3, so ties among
//! equal-f cells break toward the straight line and far fewer cells are
//! expanded. h' is not admissible: the path may cost more than the optimum;
//! pruning ([`super::prune`]) then shortens it.
//!
//! **Integer form.** With A = goal − s, B = start − s and c = cost units per
//! cell, h = c·|A| and h·cos θ = c·(A·B)/|B|, so h' = 2h + c·(A·B)/|B|:
//! two integer square roots (h, and |B| with 16 fractional bits) and one
//! 64-bit division, no floating point. The result is clamped to
//! [h, 3h] so rounding can never take it outside the paper's range.
//!
//! **A\* octile** ([`super::Algo::AStarOctile`], issue 13's search
//! speed): h = the octile distance to the nearest goal (by that distance),
//! `straight + √2·diagonal` in the same integer costs the steps use. It is
//! the exact path cost on an empty grid, so it never overestimates (corner
//! cutting forbidden only lengthens paths) and is consistent; it is integer
//! arithmetic only, where the Euclidean needs a 64-bit square root, and it
//! expands fewer nodes since it is tighter.
//!
//! **Multi-goal** (\[open\] in ALGORITHMS.md §1; our choice): h is the
//! distance to the nearest goal and θ is taken toward that same goal.

use crate::grid::Cell;
use crate::math::cost::{euclid, isqrt_round_u64, octile, COST_PER_CELL};

/// Euclidean distance (cost units) from `s` to the nearest of `goals`.
/// With no goals, 0.
pub fn euclidean(s: Cell, goals: &[Cell]) -> u32 {
    match nearest_goal(s, goals) {
        Some(g) => euclid(g.x as i32 - s.x as i32, g.y as i32 - s.y as i32),
        None => 0,
    }
}

/// Octile distance (cost units) from `s` to the nearest of `goals` by that
/// distance. With no goals, 0.
#[inline]
pub fn octile_nearest(s: Cell, goals: &[Cell]) -> u32 {
    let (sx, sy) = s.xy();
    goals
        .iter()
        .map(|g| octile(g.x as i32 - sx, g.y as i32 - sy))
        .min()
        .unwrap_or(0)
}

/// The goal nearest to `s` in straight-line distance (first one on ties).
/// Compares squared distances, so only the caller pays for a square root.
pub fn nearest_goal(s: Cell, goals: &[Cell]) -> Option<Cell> {
    let (sx, sy) = s.xy();
    let mut best: Option<(u64, Cell)> = None;
    for &g in goals {
        let (dx, dy) = ((g.x as i32 - sx) as i64, (g.y as i32 - sy) as i64);
        let d2 = (dx * dx + dy * dy) as u64;
        if best.is_none_or(|(b, _)| d2 < b) {
            best = Some((d2, g));
        }
    }
    best.map(|(_, g)| g)
}

/// The weighted heuristic h'(s) toward the nearest goal, in cost units.
pub fn oha(s: Cell, start: Cell, goals: &[Cell]) -> u32 {
    let Some(goal) = nearest_goal(s, goals) else {
        return 0;
    };
    weighted(s, start, goal)
}

/// h'(s) for a single goal.
pub fn weighted(s: Cell, start: Cell, goal: Cell) -> u32 {
    let (sx, sy) = s.xy();
    let (ax, ay) = (goal.x as i32 - sx, goal.y as i32 - sy);
    let (bx, by) = (start.x as i32 - sx, start.y as i32 - sy);
    let h = euclid(ax, ay);
    if s == start || s == goal || h == 0 {
        return h;
    }
    // |B| with 16 fractional bits: |B|² < 2^22 on any map we take, so
    // |B|²·2^32 fits in u64 and the rounding error is below 2^-17 cells.
    let b2 = (bx as i64 * bx as i64 + by as i64 * by as i64) as u64;
    let b_q16 = isqrt_round_u64(b2 << 32) as i64;
    if b_q16 == 0 {
        return h;
    }
    let dot = ax as i64 * bx as i64 + ay as i64 * by as i64;
    let c = COST_PER_CELL as i64;
    let h_cos = (c * dot * 65536) / b_q16; // = h·cos θ = c·(A·B)/|B|
    let hh = h as i64;
    (2 * hh + h_cos).clamp(hh, 3 * hh).min(u32::MAX as i64) as u32
}
