//! Cell vocabulary the coverage planners share: the four move directions,
//! "free and not yet covered", seed 000's corner rule, and the k nearest
//! points. A leaf of the coverage layer: uses `grid` and `math` only.

use crate::grid::{Cell, Grid, Layer};

/// North, south, east, west as (dx, dy) with y growing downward.
pub const N_: (i32, i32) = (0, -1);
/// South.
pub const S_: (i32, i32) = (0, 1);
/// East.
pub const E_: (i32, i32) = (1, 0);
/// West.
pub const W_: (i32, i32) = (-1, 0);

/// True when (x, y) is on the map, free and not yet covered.
#[inline]
pub fn uncovered<const GW: usize>(grid: &Grid<GW>, x: i32, y: i32) -> bool {
    grid.is_free(x, y) && !grid.get(Layer::Covered, x, y)
}

/// True when the uncovered cell (x, y) survives seed 000's pruning rule
/// (ALGORITHMS.md §1): not (N and S uncovered) and not (E and W
/// uncovered). Every uncovered region has such a cell.
pub fn is_corner<const GW: usize>(grid: &Grid<GW>, x: i32, y: i32) -> bool {
    let u = |dx: i32, dy: i32| uncovered(grid, x + dx, y + dy);
    !((u(0, -1) && u(0, 1)) || (u(1, 0) && u(-1, 0)))
}

/// The free, uncovered 4-neighbours of `cur` in `priority` order, each
/// with its move (dx, dy): the candidates of every local move rule.
pub fn open_moves<'a, const GW: usize>(
    grid: &'a Grid<GW>,
    cur: Cell,
    priority: &'a [(i32, i32); 4],
) -> impl Iterator<Item = ((i32, i32), Cell)> + 'a {
    let (x, y) = cur.xy();
    priority.iter().filter_map(move |&(dx, dy)| {
        if uncovered(grid, x + dx, y + dy) {
            Cell::from_xy(x + dx, y + dy).map(|c| ((dx, dy), c))
        } else {
            None
        }
    })
}

/// The candidate of highest `score`, the first in order among equals.
pub fn best_move<S: PartialOrd>(
    moves: impl Iterator<Item = ((i32, i32), Cell)>,
    score: impl Fn((i32, i32), Cell) -> S,
) -> Option<Cell> {
    let mut best: Option<(S, Cell)> = None;
    for (d, c) in moves {
        let s = score(d, c);
        if best.as_ref().is_none_or(|(b, _)| s > *b) {
            best = Some((s, c));
        }
    }
    best.map(|(_, c)| c)
}

/// Of the points of the best (least) `rank`, the one nearest to `from`
/// (squared Euclidean distance); ties keep list order.
pub fn nearest_of_best_rank(
    points: &[Cell],
    from: Cell,
    rank: impl Fn(Cell) -> u32,
) -> Option<Cell> {
    let d2 = |c: Cell| {
        let (dx, dy) = (c.x as i64 - from.x as i64, c.y as i64 - from.y as i64);
        dx * dx + dy * dy
    };
    points.iter().copied().min_by_key(|&c| (rank(c), d2(c)))
}

/// Copies into `out` the `k` points nearest to `from` (squared Euclidean
/// distance; ties keep list order), nearest first. Returns how many.
pub fn nearest_k(points: &[Cell], from: Cell, out: &mut [Cell], k: usize) -> usize {
    let k = k.min(out.len());
    let d2 = |c: &Cell| {
        let (dx, dy) = (c.x as i64 - from.x as i64, c.y as i64 - from.y as i64);
        dx * dx + dy * dy
    };
    crate::math::select::smallest_k(points, out.get_mut(..k).unwrap_or(&mut []), d2)
}
