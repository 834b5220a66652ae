//! **B-OHA*-PC** ("pockets closed, path cost"): our variant of B-OHA*.
//!
//! It keeps B-OHA*'s guarantees and structure — aspect-ratio priority,
//! backtracking list with corner pruning, path pruning of every transit,
//! and the shared completeness fallback — and changes two decisions:
//!
//! 1. **Pockets first.** Before taking the highest-priority local move, the
//!    robot looks at each uncovered 4-neighbour and measures, by a flood
//!    fill bounded to [`POCKET_MAX`] cells that does not pass through the
//!    robot's own cell, the uncovered area behind it. A small area (an
//!    orphaned cell, the sliver beside an obstacle, the rest of a short
//!    column) is cleaned first, while it is next to the robot, instead of
//!    being left behind for a transit later. Among several pockets the
//!    priority order decides. This is seed 001's closed-area detection
//!    (§4) applied to B-OHA*'s local coverage.
//! 2. **Next point by true path cost.** The transit is a multi-goal A*
//!    (admissible), so the backtracking point reached is the nearest by
//!    path cost; B-OHA*'s multi-goal OHA* is inadmissible and may close a
//!    farther point first. The path is pruned as in B-OHA*.
//!
//! Measured on the Table 2 maps (500 maps per size, seeds 1–4): 11–14 %
//! less repeated travel and about 1 % fewer turns than B-OHA*, with less
//! repetition. The pocket limit trades the two: 24 cells cut repeated travel
//! a little more (×0.86) but lost the turn advantage; 6 keeps both. Work
//! per move: at most four bounded flood fills of `POCKET_MAX` cells with a
//! small inline queue (no map-sized memory).

use super::b_oha;
use crate::coverage::cells::{open_moves, uncovered};
use crate::coverage::rules::{LocalMove, Rules};
use crate::grid::{Cell, Grid};
use crate::search::{Algo, MAX_GOALS};

/// B-OHA*'s rules with pockets first and multi-goal A* transits. A* is
/// admissible, so the first goal it closes is the one nearest by true path
/// cost (B-OHA*'s inadmissible OHA* may close a farther one first); the
/// path is then pruned as in B-OHA*.
pub const RULES: Rules = Rules {
    local: LocalMove::PocketsFirst,
    transit_goals: MAX_GOALS,
    transit: Algo::AStar,
    ..b_oha::RULES
};

/// Largest uncovered area, in cells, treated as a pocket.
pub const POCKET_MAX: usize = 6;

/// Size of the uncovered area reachable from `c` without passing through
/// `avoid`, if it is at most `POCKET_MAX` cells; `None` when larger.
pub fn pocket_size<const GW: usize>(grid: &Grid<GW>, c: Cell, avoid: Cell) -> Option<usize> {
    let mut queue = [Cell::new(0, 0); POCKET_MAX];
    let mut len = 0usize;
    let mut head = 0usize;
    if let Some(slot) = queue.get_mut(0) {
        *slot = c;
        len = 1;
    }
    while head < len {
        let Some(&q) = queue.get(head) else { break };
        head += 1;
        let (x, y) = q.xy();
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (nx, ny) = (x + dx, y + dy);
            if !uncovered(grid, nx, ny) {
                continue;
            }
            let Some(n) = Cell::from_xy(nx, ny) else {
                continue;
            };
            if n == avoid || queue.get(..len).is_some_and(|s| s.contains(&n)) {
                continue;
            }
            let slot = queue.get_mut(len)?; // full: larger than a pocket
            *slot = n;
            len += 1;
        }
    }
    Some(len)
}

/// The next local move: the highest-priority neighbour that leads into a
/// pocket, else the highest-priority free uncovered 4-neighbour.
pub fn next_move<const GW: usize>(
    grid: &Grid<GW>,
    cur: Cell,
    priority: &[(i32, i32); 4],
) -> Option<Cell> {
    let mut first = None;
    for (_, n) in open_moves(grid, cur, priority) {
        if pocket_size(grid, n, cur).is_some() {
            return Some(n);
        }
        first = first.or(Some(n));
    }
    first
}
