//! D* Lite: a shortest path kept up to date as cells become blocked or
//! free, without searching again from nothing (Koenig and Likhachev,
//! "D* Lite", AAAI 2002, Fig. 3; seed 004's "D*: search from the goal,
//! reuse on replanning when new obstacles appear", ALGORITHMS.md §5).
//!
//! **What.** The search runs backward, from the goal toward the robot.
//! Every cell has g (its cost to the goal as last settled) and rhs (a
//! one-step lookahead: the least `c(s, s') + g(s')` over its neighbours).
//! A cell whose two differ is *inconsistent* and waits in the open list
//! under the key `[min(g, rhs) + h(start, s) + km, min(g, rhs)]`. When cells
//! change, only the rhs of the cells next to them is recomputed, and the
//! search settles just the inconsistencies that reach the robot. `km` grows
//! by `h(last start, start)` each time the robot has moved before a change,
//! so that the keys already queued stay lower bounds (the paper's §4).
//!
//! **The graph** is the search's own: 8-connected, the octile step costs of
//! [`crate::math::cost`], no corner cutting (a diagonal needs both orthogonal
//! cells free), and h the integer octile distance, which is consistent, as
//! D* Lite requires. A changed cell changes the edges of its eight
//! neighbours and the diagonals that pass its corner, all of whose ends are
//! among those neighbours, so [`DStarLite::cells_changed`] updates the cell
//! and its eight neighbours.
//!
//! **Queue** (our choice, the paper leaves it open): the open list's heap
//! with lazy deletion, keyed `f = k1` and `g = u32::MAX − k2` so its strict
//! order (smaller f, then larger g) is the paper's lexicographic key order.
//! An entry popped whose key is not the cell's key now is dropped when
//! lower (a newer entry holds the cell) and pushed again when higher (km
//! grew since); a consistent cell's entry is dropped.
//!
//! **Memory.** 8 bytes a cell (g, rhs) and the open list: `N` and `OPEN`
//! are const generics, nothing is allocated; a full open list is
//! [`SearchError::OpenListFull`], never a lost node.

use super::open_list::{Entry, OpenList};
use super::state::{check_goal, check_start, SearchError, NEIGHBOURS};
use crate::grid::{Cell, Grid};
use crate::math::cost::{octile, COST_DIAGONAL, COST_PER_CELL};

/// The cost of no path.
const INF: u32 = u32::MAX;

/// A cell's two costs to the goal.
#[derive(Clone, Copy, Debug)]
struct Costs {
    g: u32,
    rhs: u32,
}

/// What one [`DStarLite::compute`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Replan {
    /// The cost from the start to the goal, in cost units.
    pub cost: u32,
    /// Cells expanded (made consistent) by this call.
    pub nodes_expanded: u32,
}

/// D* Lite over maps of up to `N` cells with an open list of `OPEN`
/// entries.
///
/// All-zero bytes are a valid idle state, as [`DStarLite::new`] is (every
/// call but `begin` answers `NotRunning`, and `begin` sets the costs of the
/// map's cells): a host may allocate a large one zeroed on the heap.
pub struct DStarLite<const N: usize, const OPEN: usize> {
    costs: [Costs; N],
    open: OpenList<OPEN>,
    width: u32,
    height: u32,
    start: Cell,
    last: Cell,
    goal: Cell,
    km: u32,
    ready: bool,
}

impl<const N: usize, const OPEN: usize> Default for DStarLite<N, OPEN> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, const OPEN: usize> DStarLite<N, OPEN> {
    /// An idle planner (usable in a `static`).
    pub const fn new() -> Self {
        Self {
            costs: [Costs { g: INF, rhs: INF }; N],
            open: OpenList::new(),
            width: 0,
            height: 0,
            start: Cell::new(0, 0),
            last: Cell::new(0, 0),
            goal: Cell::new(0, 0),
            km: 0,
            ready: false,
        }
    }

    /// Sets up a query from `start` to `goal` on `grid` (every cell's costs
    /// to infinity, the goal queued). Call [`DStarLite::compute`] next.
    pub fn begin<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        start: Cell,
        goal: Cell,
    ) -> Result<(), SearchError> {
        self.ready = false;
        let cells = grid.cells();
        if cells > N {
            return Err(SearchError::MapTooLarge);
        }
        check_start(grid, start)?;
        check_goal(grid, goal)?;
        for c in self.costs.iter_mut().take(cells) {
            *c = Costs { g: INF, rhs: INF };
        }
        (self.width, self.height) = (grid.width(), grid.height());
        (self.start, self.last, self.goal, self.km) = (start, start, goal, 0);
        self.open.clear();
        let gi = self.index(goal);
        self.set(gi, |c| c.rhs = 0);
        self.queue(gi)?;
        self.ready = true;
        Ok(())
    }

    /// Settles the inconsistencies that reach the start: afterwards the
    /// start's g is its cost to the goal on the grid as it is now.
    pub fn compute<const GW: usize>(&mut self, grid: &Grid<GW>) -> Result<Replan, SearchError> {
        self.check(grid)?;
        let si = self.index(self.start);
        let mut nodes = 0u32;
        loop {
            let start_key = self.key(si);
            let s = self.at(si);
            let Some(top) = self.open.pop() else { break };
            let top_key = (top.f, u32::MAX - top.g);
            if top_key >= start_key && s.rhs == s.g {
                // Not needed for the start: back in the list for later.
                self.open.push(top).map_err(|_| SearchError::OpenListFull)?;
                break;
            }
            let u = top.idx as usize;
            let now = self.key(u);
            let c = self.at(u);
            if c.g == c.rhs || top_key > now {
                continue; // consistent, or a newer entry holds the cell
            }
            if top_key < now {
                self.push(u, now)?; // km grew since it was queued
                continue;
            }
            nodes = nodes.saturating_add(1);
            self.settle(grid, u, c)?;
        }
        let s = self.at(si);
        if s.g == INF && s.rhs == INF {
            return Err(SearchError::NoPath);
        }
        Ok(Replan {
            cost: s.g.min(s.rhs),
            nodes_expanded: nodes,
        })
    }

    /// The robot now stands at `start` (it moved along the path). Cheap:
    /// nothing is searched until the next change and [`DStarLite::compute`].
    pub fn move_to<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        start: Cell,
    ) -> Result<(), SearchError> {
        self.check(grid)?;
        let (x, y) = start.xy();
        if !grid.contains(x, y) {
            return Err(SearchError::StartOffMap);
        }
        self.start = start;
        Ok(())
    }

    /// `cells` were blocked or freed on `grid` since the last call: their
    /// edges' ends get their rhs again and are queued when inconsistent.
    pub fn cells_changed<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        cells: &[Cell],
    ) -> Result<(), SearchError> {
        self.check(grid)?;
        let (gx, gy) = self.goal.xy();
        if grid.is_blocked(gx, gy) {
            self.ready = false;
            return Err(SearchError::GoalBlocked);
        }
        self.km = self.km.saturating_add(self.h(self.last, self.start));
        self.last = self.start;
        for &c in cells {
            let (x, y) = c.xy();
            for (dx, dy) in [(0, 0)].into_iter().chain(NEIGHBOURS) {
                if grid.contains(x + dx, y + dy) {
                    let i = ((y + dy) as u32 * self.width + (x + dx) as u32) as usize;
                    self.update(grid, i)?;
                }
            }
        }
        Ok(())
    }

    /// Writes the path from the start to the goal into `out` (each step to
    /// the neighbour with the least `c + g`); returns its length.
    pub fn write_path<const GW: usize>(
        &self,
        grid: &Grid<GW>,
        out: &mut [Cell],
    ) -> Result<usize, SearchError> {
        self.check(grid)?;
        let mut i = self.index(self.start);
        let gi = self.index(self.goal);
        let mut n = 0usize;
        loop {
            let slot = out.get_mut(n).ok_or(SearchError::PathBufferTooSmall)?;
            *slot = self.cell(i);
            n += 1;
            if i == gi {
                return Ok(n);
            }
            let (next, cost) = self.best_next(grid, i);
            if cost == INF || n > self.width as usize * self.height as usize {
                return Err(SearchError::NoPath);
            }
            i = next;
        }
    }

    /// Makes the popped cell `u` consistent and updates its neighbours.
    fn settle<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        u: usize,
        c: Costs,
    ) -> Result<(), SearchError> {
        if c.g > c.rhs {
            self.set(u, |k| k.g = k.rhs);
        } else {
            self.set(u, |k| k.g = INF);
            self.update(grid, u)?;
        }
        let mut moves = self.moves(grid, u);
        while moves != 0 {
            let k = moves.trailing_zeros() as usize;
            moves &= moves - 1;
            self.update(grid, self.step(u, k))?;
        }
        Ok(())
    }

    /// The paper's UpdateVertex: rhs again from the neighbours (the goal
    /// keeps 0), and the cell queued when inconsistent.
    fn update<const GW: usize>(&mut self, grid: &Grid<GW>, u: usize) -> Result<(), SearchError> {
        if u != self.index(self.goal) {
            let rhs = self.best_next(grid, u).1;
            self.set(u, |k| k.rhs = rhs);
        }
        let c = self.at(u);
        if c.g != c.rhs {
            self.queue(u)?;
        }
        Ok(())
    }

    /// The neighbour of `u` with the least step cost plus g, and that sum
    /// (INF when none leads anywhere).
    fn best_next<const GW: usize>(&self, grid: &Grid<GW>, u: usize) -> (usize, u32) {
        let mut best = (u, INF);
        let mut moves = self.moves(grid, u);
        while moves != 0 {
            let k = moves.trailing_zeros() as usize;
            moves &= moves - 1;
            let v = self.step(u, k);
            let step = if k % 2 == 1 {
                COST_DIAGONAL
            } else {
                COST_PER_CELL
            };
            let via = self.at(v).g.saturating_add(step);
            if via < best.1 {
                best = (v, via);
            }
        }
        best
    }

    /// The moves out of `u` as a mask over [`NEIGHBOURS`]: none from a
    /// blocked cell, a diagonal only with both orthogonal cells free.
    fn moves<const GW: usize>(&self, grid: &Grid<GW>, u: usize) -> u32 {
        let c = self.cell(u);
        let (x, y) = c.xy();
        if grid.is_blocked(x, y) {
            return 0;
        }
        grid.moves(x, y)
    }

    /// The index of neighbour `k` of `u` (on the map: `moves` says so).
    fn step(&self, u: usize, k: usize) -> usize {
        let (dx, dy) = NEIGHBOURS.get(k).copied().unwrap_or((0, 0));
        (u as i64 + dy as i64 * self.width as i64 + dx as i64).max(0) as usize
    }

    /// Queues `u` under its key now.
    fn queue(&mut self, u: usize) -> Result<(), SearchError> {
        let k = self.key(u);
        self.push(u, k)
    }

    fn push(&mut self, u: usize, (k1, k2): (u32, u32)) -> Result<(), SearchError> {
        self.open
            .push(Entry {
                f: k1,
                g: u32::MAX - k2,
                idx: u as u32,
            })
            .map_err(|_| SearchError::OpenListFull)
    }

    /// The paper's CalculateKey.
    fn key(&self, u: usize) -> (u32, u32) {
        let c = self.at(u);
        let m = c.g.min(c.rhs);
        let h = self.h(self.start, self.cell(u));
        (m.saturating_add(h).saturating_add(self.km), m)
    }

    fn h(&self, a: Cell, b: Cell) -> u32 {
        octile(a.x as i32 - b.x as i32, a.y as i32 - b.y as i32)
    }

    fn at(&self, i: usize) -> Costs {
        self.costs
            .get(i)
            .copied()
            .unwrap_or(Costs { g: INF, rhs: INF })
    }

    fn set(&mut self, i: usize, f: impl FnOnce(&mut Costs)) {
        if let Some(c) = self.costs.get_mut(i) {
            f(c);
        }
    }

    fn index(&self, c: Cell) -> usize {
        c.y as usize * self.width as usize + c.x as usize
    }

    fn cell(&self, i: usize) -> Cell {
        let w = (self.width as usize).max(1);
        Cell::new((i % w) as u16, (i / w) as u16)
    }

    /// The query is set up on a grid of this size.
    fn check<const GW: usize>(&self, grid: &Grid<GW>) -> Result<(), SearchError> {
        if !self.ready {
            return Err(SearchError::NotRunning);
        }
        if (grid.width(), grid.height()) != (self.width, self.height) {
            return Err(SearchError::MapChanged);
        }
        Ok(())
    }
}
