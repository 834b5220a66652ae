//! Jump point search ([`Algo::Jps`]; Harabor and Grastien 2011, "Online
//! graph pruning for pathfinding on grid maps", AAAI), in the form for
//! grids that forbid corner cutting (a diagonal step needs both straight
//! cells beside it free, as every search of ours).
//!
//! **What.** A* over the same graph as [`Algo::AStarOctile`] (same step
//! costs, same integer octile heuristic), whose expansions skip the cells
//! that only continue a straight line or a diagonal: from a node the search
//! *jumps* in each direction the arrival direction leaves open until it
//! meets the goal or a cell where an obstacle makes a turn necessary (a
//! *forced* neighbour), and only such jump points enter the open list. The
//! cost of a jump is the octile distance it covers, so the costs found are
//! A*'s: optimal (checked against A* octile on random maps and against the
//! MovingAI optima in the tests).
//!
//! **Why** (issue 13, search speed): in the open rooms of a home, or along
//! a corridor, A* pushes and pops every cell of the frontier; jump point
//! search pushes only the corners, so the open list and the per-node
//! bookkeeping shrink by orders of magnitude and what is left is a scan of
//! the obstacle bits.
//!
//! **The pruning rules without corner cutting.** Arriving diagonally
//! (dx, dy), a node continues in (dx, 0), (0, dy) and (dx, dy): any other
//! neighbour is reached at least as cheaply without it, because both cells
//! beside the diagonal step were free. Arriving straight, say (dx, 0), a
//! node continues in (dx, 0), and also to a side s, with (0, s) and
//! (dx, s), only when the side cell is free and the cell behind it,
//! (−dx, s), is blocked: otherwise the diagonal from the cell behind
//! reaches the side at least as cheaply. A diagonal jump stops at a cell
//! from which a straight jump along either of its components finds a jump
//! point. No forced neighbours arise on diagonals.
//!
//! **Paths.** Parents are jump points; every parent–child pair lies on one
//! straight or diagonal line, and [`SearchState::write_path`] fills in the
//! cells between, so the path reads cell by cell as every other search's.
//!
//! **Open list.** A jump may cover many cells, so a child's key can exceed
//! its parent's by far more than the dial's span: the search takes the
//! heap ([`super::open_list::Order::Strict`]).

use super::open_list::Entry;
use super::state::{Algo, SearchError, SearchState, NEIGHBOURS};
use crate::grid::Grid;
use crate::math::cost::{COST_DIAGONAL, COST_PER_CELL};

/// The move bit of direction (dx, dy) in the order of [`NEIGHBOURS`].
#[inline(always)]
fn bit(dx: i32, dy: i32) -> u32 {
    // (dx, dy) → k: E 0, NE 1, N 2, NW 3, W 4, SW 5, S 6, SE 7.
    const K: [u8; 9] = [3, 2, 1, 4, 0, 0, 5, 6, 7];
    let at = ((dy + 1) * 3 + (dx + 1)) as usize;
    1 << K.get(at).copied().unwrap_or(0)
}

/// The directions a node arrived at by (dx, dy) continues in, as a mask
/// in the order of [`NEIGHBOURS`] (the pruning rules in the module doc),
/// from the mask of its free neighbours ([`Grid::free_neighbours`]: the
/// side cells and the cells behind them are all neighbours); the caller
/// ands it with the node's moves.
#[inline(always)]
fn pruned(free: u32, dx: i32, dy: i32) -> u32 {
    if dx != 0 && dy != 0 {
        return bit(dx, 0) | bit(0, dy) | bit(dx, dy);
    }
    let mut dirs = bit(dx, dy);
    for s in [-1, 1] {
        // The side, across the direction of travel, and the cell behind it.
        let (sx, sy) = if dx != 0 { (0, s) } else { (s, 0) };
        if free & bit(sx, sy) != 0 && free & bit(sx - dx, sy - dy) == 0 {
            dirs |= bit(sx, sy) | bit(dx + sx, dy + sy);
        }
    }
    dirs
}

impl<const N: usize, const NW: usize, const OPEN: usize> SearchState<N, NW, OPEN> {
    /// Expands jump point `i` = (x, y): jumps in each direction its arrival
    /// leaves open (every move for the start) and relaxes the jump points
    /// found.
    pub(super) fn expand_jps<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        i: usize,
        (x, y): (i32, i32),
    ) -> Result<(), SearchError> {
        let free = grid.free_neighbours_at(i, x, y);
        let mut dirs = Grid::<GW>::moves_of(free);
        let p = self.parent_at(i);
        if p != i {
            let (px, py) = self.cell_of(p).xy();
            dirs &= pruned(free, (x - px).signum(), (y - py).signum());
        }
        let gs = self.g_at(i);
        while dirs != 0 {
            let k = dirs.trailing_zeros() as usize;
            dirs &= dirs - 1;
            let Some(&(dx, dy)) = NEIGHBOURS.get(k) else {
                continue;
            };
            let Some((jx, jy, n)) = self.jump(grid, (x, y), dx, dy) else {
                continue;
            };
            let step = if dx != 0 && dy != 0 {
                COST_DIAGONAL
            } else {
                COST_PER_CELL
            };
            let cand = gs.saturating_add(step.saturating_mul(n));
            self.relax_jump(grid, (jx, jy), i, cand)?;
        }
        Ok(())
    }

    /// Records jump point (x, y) reached from `parent` at cost `cand`, and
    /// pushes it, unless it is closed or already reached as cheaply.
    #[inline(always)]
    fn relax_jump<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        (x, y): (i32, i32),
        parent: usize,
        cand: u32,
    ) -> Result<(), SearchError> {
        let Some(ji) = grid.index(x, y) else {
            return Ok(());
        };
        if self.closed.get(ji) || (self.seen.get(ji) && cand >= self.g_at(ji)) {
            return Ok(());
        }
        self.set_node(ji, cand, parent as u32);
        let f = cand.saturating_add(self.octile_h(x, y));
        self.open
            .push(Entry {
                f,
                g: cand,
                idx: ji as u32,
            })
            .map_err(|_| SearchError::OpenListFull)
    }

    /// Whether (x, y) is a goal of the query.
    #[inline(always)]
    fn goal_xy(&self, x: i32, y: i32) -> bool {
        self.goals()
            .iter()
            .any(|g| g.x as i32 == x && g.y as i32 == y)
    }

    /// Jumps from (x, y) in direction (dx, dy): the first jump point on the
    /// way and the steps to it, or `None` at an obstacle or the map's edge.
    fn jump<const GW: usize>(
        &self,
        grid: &Grid<GW>,
        (x, y): (i32, i32),
        dx: i32,
        dy: i32,
    ) -> Option<(i32, i32, u32)> {
        if dx == 0 || dy == 0 {
            return self.jump_straight(grid, (x, y), dx, dy);
        }
        let (mut cx, mut cy, mut n) = (x, y, 0u32);
        loop {
            // The diagonal step, without cutting a corner.
            if grid.is_blocked(cx + dx, cy + dy)
                || grid.is_blocked(cx + dx, cy)
                || grid.is_blocked(cx, cy + dy)
            {
                return None;
            }
            cx += dx;
            cy += dy;
            n += 1;
            if self.goal_xy(cx, cy)
                || self.jump_straight(grid, (cx, cy), dx, 0).is_some()
                || self.jump_straight(grid, (cx, cy), 0, dy).is_some()
            {
                return Some((cx, cy, n));
            }
        }
    }

    /// A straight jump from (x, y) by (dx, dy) (one of them 0).
    #[inline(always)]
    fn jump_straight<const GW: usize>(
        &self,
        grid: &Grid<GW>,
        (x, y): (i32, i32),
        dx: i32,
        dy: i32,
    ) -> Option<(i32, i32, u32)> {
        if dy == 0 {
            let n = self.scan_row(grid, (x, y), dx)?;
            Some((x + dx * n as i32, y, n))
        } else {
            let n = self.scan_column(grid, (x, y), dy)?;
            Some((x, y + dy * n as i32, n))
        }
    }

    /// A jump along row `y` from `x` by `dx` = ±1, 31 cells at a time: the
    /// steps to the first cell that is a goal or has a forced neighbour (a
    /// free cell beside the row whose cell behind is blocked), or `None` if
    /// a blocked cell comes first.
    #[inline(always)]
    fn scan_row<const GW: usize>(&self, grid: &Grid<GW>, at: (i32, i32), dx: i32) -> Option<u32> {
        if dx > 0 {
            self.scan_row_toward::<true, GW>(grid, at)
        } else {
            self.scan_row_toward::<false, GW>(grid, at)
        }
    }

    /// [`Self::scan_row`] east (`EAST`) or west. Each step reads the 32
    /// cells from the current one on (bit 0 the current one going east,
    /// bit 31 going west), so the words overlap by one cell: the cell
    /// behind the first new one.
    fn scan_row_toward<const EAST: bool, const GW: usize>(
        &self,
        grid: &Grid<GW>,
        (x, y): (i32, i32),
    ) -> Option<u32> {
        let mut c = x;
        loop {
            let first = if EAST { c } else { c - 31 };
            let [a, row, b] = grid.rows3(first, y);
            let goals = self.goals_on_row(first, y);
            // The steps to the first stop.
            let j = if EAST {
                let forced = (!a & a << 1) | (!b & b << 1);
                let stop = (row | forced | goals) & !1;
                stop.trailing_zeros() // 32 when none
            } else {
                let forced = (!a & a >> 1) | (!b & b >> 1);
                let stop = (row | forced | goals) & !(1 << 31);
                stop.leading_zeros() // 31 − the bit; 32 when none
            };
            if j < 32 {
                let bit = if EAST { j } else { 31 - j };
                if row >> bit & 1 != 0 {
                    return None;
                }
                return Some((c - x).unsigned_abs() + j);
            }
            c += if EAST { 31 } else { -31 };
        }
    }

    /// The goals among cells `x ..= x + 31` of row `y`, as bits 0..32.
    #[inline(always)]
    fn goals_on_row(&self, x: i32, y: i32) -> u32 {
        let mut m = 0u32;
        for g in self.goals() {
            let j = g.x as i32 - x;
            if g.y as i32 == y && (0..32).contains(&j) {
                m |= 1 << j;
            }
        }
        m
    }

    /// A jump along column `x` from `y` by `dy` = ±1, a row of three cells
    /// at a time: as [`Self::scan_row`], one cell per step.
    fn scan_column<const GW: usize>(
        &self,
        grid: &Grid<GW>,
        (x, y): (i32, i32),
        dy: i32,
    ) -> Option<u32> {
        // Bits 0, 1, 2: cells x − 1, x, x + 1 of a row.
        let column = grid.column3(x);
        let mut behind = column.read(y);
        let (mut cy, mut n) = (y, 0u32);
        loop {
            cy += dy;
            let here = column.read(cy);
            if here & 0b010 != 0 {
                return None;
            }
            n += 1;
            if !here & behind & 0b101 != 0 || self.goal_xy(x, cy) {
                return Some(n);
            }
            behind = here;
        }
    }

    /// Whether the current query's parents are jump points, whose gaps
    /// [`SearchState::write_path`] fills in.
    pub(super) fn jumps(&self) -> bool {
        self.algo == Algo::Jps
    }
}
