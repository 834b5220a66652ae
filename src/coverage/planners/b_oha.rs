//! B-OHA*: backtracking bidirectional boustrophedon with OHA* transit
//! (seed 000, ALGORITHMS.md §1). The step loop is shared
//! ([`crate::coverage`]); this file holds B-OHA*'s own rules, and
//! [`RULES`] names them for the loop.
//!
//! - **Traversal priority by aspect ratio** (§2.1): when the map's N–S
//!   extent exceeds its E–W extent the move priority is N, S, E, W (sweep
//!   columns), otherwise W, E, S, N (sweep rows), so the sweep runs along
//!   the long side and turns less. The extent is the map's (the paper's
//!   "working environment").
//! - **Local coverage** (Algorithm 2, steps 2–3): at each cell, every
//!   uncovered free neighbour (all eight, S1..S8) enters the backtracking
//!   list; the robot moves one cell to the highest-priority free uncovered
//!   4-neighbour, which leaves the list.
//! - **Pruning at a critical point** (§2.2): covered points leave the list,
//!   and so does every point with (S3 and S7 uncovered) or (S1 and S5
//!   uncovered): it sits inside an uncovered run, not at its corner.
//! - **Transit** (§2.3): multi-goal OHA* to the backtracking points, then
//!   path pruning (Algorithm 1). The digest leaves the goal range open; we
//!   take the [`MAX_GOALS`] points nearest in straight line (all of them on
//!   the paper's maps) and θ toward the nearest goal.

use crate::coverage::cells::{is_corner, uncovered, E_, N_, S_, W_};
use crate::coverage::list::BacktrackList;
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::{Cell, Grid};
use crate::search::{Algo, MAX_GOALS, NEIGHBOURS};

/// B-OHA*'s rules: priority by aspect ratio, neighbours listed on arrival
/// and pruned to corners, multi-goal OHA* transits, pruned.
pub const RULES: Rules = Rules {
    priority: Priority::ByAspect,
    local: LocalMove::Priority,
    list: ListRule::NeighboursPrunedToCorners,
    transit_goals: MAX_GOALS,
    transit: Algo::Oha,
    prune_transit: true,
};

/// Move priority from the map's aspect ratio.
pub fn priority<const GW: usize>(grid: &Grid<GW>) -> [(i32, i32); 4] {
    sweep_priority(grid.height() > grid.width())
}

/// The move priority that sweeps columns (N, S, E, W) or rows (W, E, S,
/// N).
pub fn sweep_priority(columns: bool) -> [(i32, i32); 4] {
    if columns {
        [N_, S_, E_, W_]
    } else {
        [W_, E_, S_, N_]
    }
}

/// Pushes every uncovered free 8-neighbour of the robot's cell `cur`.
pub fn push_neighbours<const LCAP: usize, const NW: usize, const GW: usize>(
    list: &mut BacktrackList<LCAP, NW>,
    grid: &Grid<GW>,
    cur: Cell,
) {
    let (x, y) = cur.xy();
    for (dx, dy) in NEIGHBOURS {
        if uncovered(grid, x + dx, y + dy) {
            if let Some(c) = Cell::from_xy(x + dx, y + dy) {
                list.push(grid, c);
            }
        }
    }
}

/// The pruning at a critical point: only uncovered corner cells stay
/// ([`is_corner`]).
pub fn prune_list<const LCAP: usize, const NW: usize, const GW: usize>(
    list: &mut BacktrackList<LCAP, NW>,
    grid: &Grid<GW>,
) {
    list.retain(grid, |g, c| {
        let (x, y) = c.xy();
        uncovered(g, x, y) && is_corner(g, x, y)
    });
}
