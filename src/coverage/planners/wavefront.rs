//! Wavefront coverage (seed 004, ALGORITHMS.md §5; Zelinsky et al. 1993).
//!
//! A distance transform spreads from the goal, the run's start (in the
//! mission, the dock): every free cell holds its 4-connected step distance
//! to it. The robot always steps to the **highest-valued unvisited
//! neighbour**, so it sweeps the far end first and works its way back
//! toward the goal, finishing near it; ties go by the fixed order N, S, E,
//! W.
//!
//! **Our decisions.**
//! - The transform is held in the planner's per-cell field (2 bytes a
//!   cell; distances saturate at 65,534 steps, beyond which the ranking is
//!   flat but coverage stays complete; a build without one, the firmware's, refuses the planner at
//!   start with [`crate::coverage::CoverageError::NoField`]).
//! - It is computed by forward and backward raster passes until nothing
//!   changes (no queue, no memory beyond the field). Each pass pair is
//!   O(cells); a map needs about as many pairs as its shortest paths have
//!   bends against the raster (a handful for rooms, more for a maze). It
//!   is built at start and again whenever the planner rescans the grid
//!   (the map may have grown, in unknown mode).
//! - **Dead ends.** When every neighbour is visited, the seed's method has
//!   no rule; ours is the shared one: the rescan's corner cells of the
//!   uncovered regions, the nearest reached by a multi-goal A* with the
//!   octile heuristic, pruned.

use crate::coverage::cells::{best_move, open_moves, E_, N_, S_, W_};
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::{Cell, Grid};
use crate::search::{Algo, MAX_GOALS};

/// The wavefront's rules.
pub const RULES: Rules = Rules {
    priority: Priority::Fixed([N_, S_, E_, W_]),
    local: LocalMove::Wavefront,
    list: ListRule::RescanOnly,
    transit_goals: MAX_GOALS,
    transit: Algo::AStarOctile,
    prune_transit: true,
};

/// Value of a cell the transform does not reach (an obstacle, or free
/// space cut off from the goal).
pub const UNREACHED: u16 = u16::MAX;

/// Writes into `field` every free cell's 4-connected step distance to
/// `goal` ([`UNREACHED`] where none). `field` holds at least the grid's
/// cells (the caller checks).
pub fn build<const GW: usize>(grid: &Grid<GW>, field: &mut [u16], goal: Cell) {
    let (w, h) = (grid.width() as usize, grid.height() as usize);
    let Some(cells) = field.get_mut(..w * h) else {
        return;
    };
    cells.fill(UNREACHED);
    let (gx, gy) = goal.xy();
    if grid.is_blocked(gx, gy) {
        return;
    }
    if let Some(g) = cells.get_mut(gy as usize * w + gx as usize) {
        *g = 0;
    }
    while relax(grid, cells, w, h, true) | relax(grid, cells, w, h, false) {}
}

/// One raster pass (forward: from the west and north neighbours; backward:
/// from the east and south ones). True when a value fell.
fn relax<const GW: usize>(grid: &Grid<GW>, d: &mut [u16], w: usize, h: usize, fwd: bool) -> bool {
    let mut changed = false;
    for k in 0..w * h {
        let i = if fwd { k } else { w * h - 1 - k };
        let (x, y) = (i % w, i / w);
        if grid.is_blocked(x as i32, y as i32) {
            continue;
        }
        let (a, b) = if fwd {
            (
                x.checked_sub(1).map(|_| i - 1),
                y.checked_sub(1).map(|_| i - w),
            )
        } else {
            ((x + 1 < w).then_some(i + 1), (y + 1 < h).then_some(i + w))
        };
        let via = |j: Option<usize>| {
            j.and_then(|j| d.get(j))
                // One step more, held at the largest distance (UNREACHED − 1).
                .map_or(UNREACHED, |&v| if v >= UNREACHED - 1 { v } else { v + 1 })
        };
        let best = via(a).min(via(b));
        if let Some(v) = d.get_mut(i) {
            if best < *v {
                *v = best;
                changed = true;
            }
        }
    }
    changed
}

/// The next local move: the unvisited 4-neighbour of highest value
/// (`priority` order among equals); `None` at a dead end.
pub fn next_move<const GW: usize>(
    grid: &Grid<GW>,
    field: &[u16],
    cur: Cell,
    priority: &[(i32, i32); 4],
) -> Option<Cell> {
    let w = grid.width() as usize;
    best_move(open_moves(grid, cur, priority), |_, n| {
        let v = field
            .get(n.y as usize * w + n.x as usize)
            .copied()
            .unwrap_or(0);
        // An unreached cell (cut off from the goal by a wall the robot has
        // just found) ranks lowest, not highest.
        if v == UNREACHED {
            0
        } else {
            v
        }
    })
}
