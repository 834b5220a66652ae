//! Region decomposition with inner-spiral and comb traversal (seed 003,
//! ALGORITHMS.md §4), in our reading on a grid.
//!
//! The seed splits the free space along the edges of concave (U-shaped)
//! obstacles and the map boundary, sweeps the inside of each U with a comb
//! (boustrophedon) and the regions around convex obstacles with an inner
//! spiral, visits the regions counter-clockwise, and joins them by the
//! "two-point method". Its maps are figures, so the decomposition is ours:
//!
//! - **Walls and furniture.** An obstacle joined (8-connected) to the
//!   map's edge is the boundary; one standing free is furniture.
//! - **Which cells lie inside a U.** A free cell whose rays in the four
//!   directions meet furniture on exactly three sides (the fourth meets the
//!   boundary, or nothing within [`RAY`] cells) lies inside a U-shaped
//!   obstacle, open on the fourth side. Its class is the comb along the
//!   open axis ([`COMB_NS`], [`COMB_EW`]); every other free cell is
//!   [`SPIRAL`]: the space around convex furniture, swept by the inner
//!   spiral. The classes are held in the planner's per-cell field, and a
//!   region is a 4-connected group of one class: the robot's local moves
//!   never leave its class, so it finishes a region before the next. We do
//!   not cut the spiral space further along the U's extended edges (the
//!   seed's 2–4 sub-regions): the spiral follows the edges there anyway.
//! - **Inside a region.** Comb: lanes along the U's depth (priority N, S,
//!   E, W for a pocket open north or south; W, E, S, N otherwise). Spiral:
//!   the robot keeps the boundary and the swept cells on its right (a
//!   right turn when the cell there is open, else straight on, else
//!   left): round the region's edge, then inward lap by lap. Measured
//!   against "straight on until blocked, then left" on the 11 maps of
//!   `bench coverage` (flats, real homes, rooms64, maze49): path 1.25
//!   against 1.39 times the best planner's; on seed 003's map 20.8 %
//!   against 14.5 % repeated.
//! - **Region order.** When a region is done, the next goal is, among the
//!   corner cells of every region's uncovered part (the shared rescan, by
//!   class), the first counter-clockwise around the map's centre from the
//!   robot (in eighths of a turn), the nearest within that eighth.
//! - **Joining regions.** The two-point method heads straight for the
//!   target and sidesteps obstacles; ours is the shared transit, A* with
//!   the octile heuristic, pruned, which is never longer.

use super::bcd;
use crate::coverage::cells::{open_moves, E_, N_, S_, W_};
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::{Cell, Grid};
use crate::search::Algo;

/// Seed 003's rules.
pub const RULES: Rules = Rules {
    priority: Priority::Fixed([N_, S_, E_, W_]),
    local: LocalMove::Regions,
    list: ListRule::RescanOnly,
    transit_goals: 1,
    transit: Algo::AStarOctile,
    prune_transit: true,
};

/// How far a ray looks for furniture, cells.
pub const RAY: i32 = 64;
/// A cell swept by the inner spiral.
pub const SPIRAL: u16 = 1;
/// A cell inside a pocket open north or south: comb along the columns.
pub const COMB_NS: u16 = 2;
/// A cell inside a pocket open east or west: comb along the rows.
pub const COMB_EW: u16 = 3;
/// The field's value on the boundary (an obstacle joined to the map's
/// edge).
const WALL: u16 = u16::MAX;
/// The field's value on furniture (an obstacle standing free).
const FURNITURE: u16 = u16::MAX - 1;

/// True when the ray from (x, y) toward (dx, dy) meets furniture first
/// (not the boundary, and within [`RAY`] cells).
fn meets_furniture<const GW: usize>(
    grid: &Grid<GW>,
    f: &[u16],
    x: i32,
    y: i32,
    (dx, dy): (i32, i32),
) -> bool {
    for k in 1..=RAY {
        let (px, py) = (x + k * dx, y + k * dy);
        if grid.is_blocked(px, py) {
            return grid.index(px, py).and_then(|i| f.get(i)) == Some(&FURNITURE);
        }
    }
    false
}

/// The class of the free cell (x, y), the obstacles marked in `f`.
fn class<const GW: usize>(grid: &Grid<GW>, f: &[u16], x: i32, y: i32) -> u16 {
    let furniture: [bool; 4] = [N_, S_, E_, W_].map(|d| meets_furniture(grid, f, x, y, d));
    match furniture {
        [false, true, true, true] | [true, false, true, true] => COMB_NS,
        [true, true, false, true] | [true, true, true, false] => COMB_EW,
        _ => SPIRAL,
    }
}

/// Marks every obstacle cell as boundary or furniture: edge cells are
/// boundary, and so is every obstacle cell 8-connected to one (raster
/// passes until nothing changes).
fn mark_obstacles<const GW: usize>(grid: &Grid<GW>, f: &mut [u16], w: i32, h: i32) {
    for (i, v) in f.iter_mut().enumerate() {
        let (x, y) = (i as i32 % w, i as i32 / w);
        let edge = x == 0 || y == 0 || x == w - 1 || y == h - 1;
        *v = match (grid.is_blocked(x, y), edge) {
            (false, _) => 0,
            (true, true) => WALL,
            (true, false) => FURNITURE,
        };
    }
    let mut changed = true;
    while changed {
        changed = false;
        for k in 0..2 * f.len() {
            let i = if k < f.len() { k } else { 2 * f.len() - 1 - k };
            let (x, y) = (i as i32 % w, i as i32 / w);
            if f.get(i) != Some(&FURNITURE) {
                continue;
            }
            let walled = crate::search::NEIGHBOURS
                .iter()
                .any(|&(dx, dy)| grid.index(x + dx, y + dy).and_then(|j| f.get(j)) == Some(&WALL));
            if let (true, Some(v)) = (walled, f.get_mut(i)) {
                *v = WALL;
                changed = true;
            }
        }
    }
}

/// Writes every free cell's class into `field` (obstacles keep their
/// boundary or furniture mark).
pub fn build<const GW: usize>(grid: &Grid<GW>, field: &mut [u16]) {
    let (w, h) = (grid.width() as i32, grid.height() as i32);
    let Some(f) = field.get_mut(..(w * h) as usize) else {
        return;
    };
    mark_obstacles(grid, f, w, h);
    for i in 0..f.len() {
        let (x, y) = (i as i32 % w, i as i32 / w);
        if grid.is_free(x, y) {
            let c = class(grid, f, x, y);
            if let Some(v) = f.get_mut(i) {
                *v = c;
            }
        }
    }
}

/// The next local move inside the robot's region (see the module docs).
pub fn next_move<const GW: usize>(
    grid: &Grid<GW>,
    field: &[u16],
    cur: Cell,
    heading: (i32, i32),
) -> Option<Cell> {
    let here = bcd::label(grid, field, cur.x as i32, cur.y as i32);
    let priority = match here {
        COMB_NS => [N_, S_, E_, W_],
        COMB_EW => [W_, E_, S_, N_],
        _ => {
            // Right, straight, left, back (y grows downward: right of
            // (dx, dy) is (−dy, dx)).
            // The last move may be a diagonal transit: keep its east–west part.
            let (dx, dy) = match heading {
                (0, 0) => E_,
                (hx, 0) | (hx, _) if hx != 0 => (hx, 0),
                h => h,
            };
            [(-dy, dx), (dx, dy), (dy, -dx), (-dx, -dy)]
        }
    };
    let next = open_moves(grid, cur, &priority)
        .find(|(_, c)| bcd::label(grid, field, c.x as i32, c.y as i32) == here)
        .map(|(_, c)| c);
    next
}

/// A pseudo-angle of (dx, dy) (y up), 0..4096 for a whole turn,
/// counter-clockwise from east: monotone in the true angle, no
/// trigonometry.
pub fn pseudo_angle(dx: i64, dy: i64) -> i64 {
    let q = |a: i64, b: i64| if a + b == 0 { 0 } else { 1024 * b / (a + b) };
    match (dx >= 0, dy >= 0) {
        _ if dx == 0 && dy == 0 => 0,
        (true, true) => q(dx, dy),
        (false, true) => 1024 + q(dy, -dx),
        (false, false) => 2048 + q(-dx, -dy),
        (true, false) => 3072 + q(-dy, dx),
    }
}

/// The goal's rank: the eighth of a turn, counter-clockwise around the
/// map's centre, from the robot to the point.
pub fn ccw_rank<const GW: usize>(grid: &Grid<GW>, from: Cell, c: Cell) -> u32 {
    let (cx, cy) = (grid.width() as i64 / 2, grid.height() as i64 / 2);
    let angle = |p: Cell| pseudo_angle(p.x as i64 - cx, cy - p.y as i64);
    ((angle(c) - angle(from)).rem_euclid(4096) / 512) as u32
}
