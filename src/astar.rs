//! A* (Hart, Nilsson and Raphael 1968; ALGORITHMS.md §5 and seed 000 eq. 1).
//!
//! f(s) = g(s) + h(s) with h the **Euclidean** distance to the nearest goal:
//! seed 000 calls this the "traditional A*" it compares OHA* against. The
//! Euclidean distance never exceeds the octile distance, so h is admissible
//! and consistent on the 8-connected grid and the path cost is optimal.
//! The search loop itself is shared: see [`crate::search`].

use crate::cost::euclid;
use crate::grid::{Cell, Grid};
use crate::search::{Algo, SearchError, SearchState, SearchStats};

/// Euclidean distance (cost units) from `s` to the nearest of `goals`.
/// With no goals, 0.
pub fn heuristic(s: Cell, goals: &[Cell]) -> u32 {
    match nearest_goal(s, goals) {
        Some(g) => euclid(g.x as i32 - s.x as i32, g.y as i32 - s.y as i32),
        None => 0,
    }
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

/// Runs A* from `start` to `goal` to completion.
pub fn astar<const N: usize, const NW: usize, const OPEN: usize, const GW: usize>(
    state: &mut SearchState<N, NW, OPEN>,
    grid: &Grid<GW>,
    start: Cell,
    goal: Cell,
) -> Result<SearchStats, SearchError> {
    state.search(grid, start, &[goal], Algo::AStar)
}
