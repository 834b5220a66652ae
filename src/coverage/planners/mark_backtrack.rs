//! Mark backtracking with closed-area detection (seed 001, ALGORITHMS.md
//! §2), on a known grid and online as the map grows.
//!
//! - **Motion.** Boustrophedon with the priority E > W > N > S; at an
//!   obstacle the robot turns to the next direction by priority.
//! - **Marks** (§3.2). Arriving at a cell while moving east (west): when
//!   the cell ahead and the cell to the north are both free and uncovered
//!   and the north-east (north-west) diagonal is an obstacle, the north
//!   cell becomes a *north point*: a corner of unexplored space the sweep
//!   is about to pass. South points likewise. A point leaves the list once
//!   covered.
//! - **Dead point.** The nearest north point (Euclidean), else the nearest
//!   south point, else the nearest uncovered cell. The seed reaches it with
//!   A* (8-neighbour, g Euclidean, h Manhattan); Manhattan over-estimates a
//!   diagonal, so ours keeps A* with the Euclidean heuristic (optimal).
//!   The list holds cells only; a point's kind is read from the grid when
//!   it is chosen: a north point has the swept cell south of it covered, a
//!   south point the cell north of it ([`kind`]), so no tag is stored.
//!   "The nearest uncovered cell" is the nearest cell of the shared
//!   completeness rescan, which lists every uncovered region's corners.
//! - **Closed areas** (§4). While sweeping, an uncovered area next to the
//!   robot that the path and the obstacles have closed is cleaned at once:
//!   the pockets-first move rule of [`super::b_oha_pc`] (a bounded flood
//!   fill that does not pass the robot's cell, up to
//!   [`super::b_oha_pc::POCKET_MAX`] cells). Our decision: the seed follows
//!   a closed area's boundary and sweeps back; a pocket that small is
//!   cleaned by entering it, and a larger closed area keeps its marks and
//!   is reached by the dead-point rule.
//! - **Dynamic matrix** (§3.3). The seed grows its matrix from four range
//!   readings (E, W, N, S). In the mission's unknown mode the evidence map
//!   plays that part: each lidar revolution turns every beam into free and
//!   occupied cells, so the planning grid grows in all directions at once,
//!   where the seed's four readings grow it along the robot's row and
//!   column. Cells not yet seen are obstacles to the planner, as cells
//!   outside the seed's matrix are, and the planner re-reads the grid at
//!   every step.

use crate::coverage::cells::{nearest_of_best_rank, uncovered, E_, N_, S_, W_};
use crate::coverage::list::BacktrackList;
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::{Cell, Grid, Layer};
use crate::search::Algo;

/// Mark backtracking's rules: E > W > N > S, pockets (closed areas) first,
/// north and south marks, one goal reached by Euclidean A*.
pub const RULES: Rules = Rules {
    priority: Priority::Fixed([E_, W_, N_, S_]),
    local: LocalMove::PocketsFirst,
    list: ListRule::Marks,
    transit_goals: 1,
    transit: Algo::AStar,
    prune_transit: true,
};

/// Sets the marks on arrival at `cur` after a move in direction `heading`
/// (unit steps; marks are set only while moving east or west).
pub fn push_marks<const LCAP: usize, const NW: usize, const GW: usize>(
    list: &mut BacktrackList<LCAP, NW>,
    grid: &Grid<GW>,
    cur: Cell,
    heading: (i32, i32),
) {
    let (dx, dy) = heading;
    if dy != 0 || dx == 0 {
        return;
    }
    let (x, y) = cur.xy();
    if !uncovered(grid, x + dx, y) {
        return;
    }
    for (_, side) in [N_, S_] {
        if uncovered(grid, x, y + side) && grid.is_blocked(x + dx, y + side) {
            if let Some(c) = Cell::from_xy(x, y + side) {
                list.push(grid, c);
            }
        }
    }
}

/// A point's rank at a dead point: 0 for a north point (the cell south of
/// it is covered), 1 for a south point, 2 for any other uncovered cell.
pub fn kind<const GW: usize>(grid: &Grid<GW>, c: Cell) -> u8 {
    let (x, y) = c.xy();
    if grid.get(Layer::Covered, x, y + 1) {
        0
    } else if grid.get(Layer::Covered, x, y - 1) {
        1
    } else {
        2
    }
}

/// The goal at a dead point: the nearest point of the best rank
/// ([`kind`]), straight-line distance, ties in list order.
pub fn choose<const GW: usize>(points: &[Cell], grid: &Grid<GW>, from: Cell) -> Option<Cell> {
    nearest_of_best_rank(points, from, |c| u32::from(kind(grid, c)))
}
