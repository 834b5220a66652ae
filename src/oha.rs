//! OHA*: A* with an orientation-weighted heuristic (seed 000 §2.3, eq. 2).
//!
//! h'(s) = (2 + cos θ)·h(s), θ ∈ [0, π] the angle at `s` between the
//! vectors s→goal and s→start, and cos θ = −1 (h' = h) when `s` is the
//! start or the goal. h is the Euclidean distance. Cells on the start–goal
//! segment keep weight 1, cells off to the side get up to 3, so ties among
//! equal-f cells break toward the straight line and far fewer cells are
//! expanded. h' is not admissible: the path may cost more than the optimum;
//! pruning ([`crate::prune`]) then shortens it.
//!
//! **Integer form.** With A = goal − s, B = start − s and c = cost units per
//! cell, h = c·|A| and h·cos θ = c·(A·B)/|B|, so h' = 2h + c·(A·B)/|B|:
//! two integer square roots (h, and |B| with 16 fractional bits) and one
//! 64-bit division, no floating point. The result is clamped to
//! [h, 3h] so rounding can never take it outside the paper's range.
//!
//! **Multi-goal** (\[open\] in ALGORITHMS.md §1; our choice): h is the
//! distance to the nearest goal and θ is taken toward that same goal.

use crate::astar::nearest_goal;
use crate::cost::{euclid, isqrt_round_u64, COST_PER_CELL};
use crate::grid::{Cell, Grid};
use crate::search::{Algo, SearchError, SearchState, SearchStats};

/// The weighted heuristic h'(s) toward the nearest goal, in cost units.
pub fn heuristic(s: Cell, start: Cell, goals: &[Cell]) -> u32 {
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

/// Runs OHA* from `start` to `goal` to completion.
pub fn oha<const N: usize, const NW: usize, const OPEN: usize, const GW: usize>(
    state: &mut SearchState<N, NW, OPEN>,
    grid: &Grid<GW>,
    start: Cell,
    goal: Cell,
) -> Result<SearchStats, SearchError> {
    state.search(grid, start, &[goal], Algo::Oha)
}
