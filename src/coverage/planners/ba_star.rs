//! BA* (Viet, Dang, Chung and Nguyen, Applied Intelligence 2013), the
//! first baseline of seed 000 (ALGORITHMS.md §1).
//!
//! - Boustrophedon with the fixed priority N, S, E, W.
//! - At each critical point the backtracking list is rebuilt: every covered
//!   cell `s` with b(s) ≥ 1, where
//!   b(s) = μ(S1,S8) + μ(S1,S2) + μ(S5,S6) + μ(S5,S4) + μ(S7,S6) + μ(S7,S8)
//!   and μ(a, b) = 1 when `a` is free and uncovered and `b` is blocked
//!   (obstacle, off the map, or covered). Every point of every rebuild
//!   counts towards `backtrack_points_total`, as the paper's ≈ 3 885 imply.
//! - The nearest point (Euclidean) is reached with A* and then smoothed by
//!   line of sight (the same pruning as Algorithm 1).

use crate::coverage::cells::{uncovered, E_, N_, S_, W_};
use crate::coverage::list::BacktrackList;
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::{Cell, Grid, Layer};
use crate::search::Algo;

/// BA*'s rules: fixed priority N, S, E, W, the list rebuilt at every
/// critical point, one goal (the nearest point) reached by A*, pruned.
pub const RULES: Rules = Rules {
    priority: Priority::Fixed([N_, S_, E_, W_]),
    local: LocalMove::Priority,
    list: ListRule::RebuiltFromCovered,
    transit_goals: 1,
    transit: Algo::AStar,
    prune_transit: true,
};

/// b(s) for the cell (x, y).
pub fn b<const GW: usize>(grid: &Grid<GW>, x: i32, y: i32) -> u32 {
    let free_unc = |dx: i32, dy: i32| uncovered(grid, x + dx, y + dy);
    let blocked = |dx: i32, dy: i32| {
        grid.is_blocked(x + dx, y + dy) || grid.get(Layer::Covered, x + dx, y + dy)
    };
    let mu = |a: (i32, i32), b: (i32, i32)| u32::from(free_unc(a.0, a.1) && blocked(b.0, b.1));
    // S1=E, S2=NE, S4=NW, S5=W, S6=SW, S7=S, S8=SE (y grows downward).
    let (s1, s2, s4, s5, s6, s7, s8) =
        ((1, 0), (1, -1), (-1, -1), (-1, 0), (-1, 1), (0, 1), (1, 1));
    mu(s1, s8) + mu(s1, s2) + mu(s5, s6) + mu(s5, s4) + mu(s7, s6) + mu(s7, s8)
}

/// Rebuilds the list from every covered cell with b(s) ≥ 1.
pub fn rebuild_list<const LCAP: usize, const NW: usize, const GW: usize>(
    list: &mut BacktrackList<LCAP, NW>,
    grid: &Grid<GW>,
) {
    list.retain(grid, |_, _| false);
    for y in 0..grid.height() as i32 {
        for x in 0..grid.width() as i32 {
            if grid.is_free(x, y) && grid.get(Layer::Covered, x, y) && b(grid, x, y) > 0 {
                if let Some(c) = Cell::from_xy(x, y) {
                    list.push(grid, c);
                }
            }
        }
    }
}
