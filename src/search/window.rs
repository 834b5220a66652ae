//! A search over a bounded window of a larger grid.
//!
//! The search state costs 8 bytes a cell ([`SearchState`]), so a search
//! over the whole 5 cm map of a 12 × 12 m home (57,600 cells: 460 KB) can
//! never fit in the STM32F411's 128 KiB. The fine searches (detours, the
//! edge pass's transits, the way home's last stretch) are local, so they
//! run on a copy of the obstacles inside a window of at most `N` cells;
//! the long ways are routed on the planning grid first (issue 11 §3).
//!
//! **Where the window lies.** When the whole grid fits in `N` cells, the
//! window is the whole grid and the search is exactly the one over the
//! grid itself (the host's capacities: the host's figures do not change).
//! Otherwise the window is a square of side ⌊√N⌋ (clamped to the grid):
//! centred on the box around the start and the goals when that box fits
//! in it; else centred on the start, keeping the goals inside it, and
//! [`SearchError::OutOfWindow`] when none is. Cells outside the window
//! read as obstacles, so a path never leaves it.
//!
//! **The search state is lent, not owned.** The caller passes a
//! [`SearchState`] to every call: on the robot it is the coverage
//! planner's, shared in time (issue 11 §3: one search state instead of
//! two, about 20 KB fewer). The planner searches only between fine
//! searches, but nothing relies on it: each side remembers the
//! [`SearchState::query_id`] its own `begin` left, and a query whose state
//! was taken meanwhile fails with [`SearchError::Preempted`] (here) or is
//! begun again (the planner) instead of reading another query's nodes.

use super::{Algo, Progress, SearchError, SearchState, MAX_GOALS};
use crate::grid::{Cell, Grid};
use crate::math::cost::isqrt_u64;

/// A window on a larger grid: lower corner and size, cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Window {
    /// Lower corner on the larger grid.
    pub x0: u16,
    /// Lower corner on the larger grid.
    pub y0: u16,
    /// Width, cells.
    pub w: u16,
    /// Height, cells.
    pub h: u16,
}

impl Window {
    /// True when `c` (a larger-grid cell) lies inside.
    pub fn contains(&self, c: Cell) -> bool {
        c.x >= self.x0 && c.y >= self.y0 && c.x - self.x0 < self.w && c.y - self.y0 < self.h
    }

    /// `c` (inside) in window cells.
    fn local(&self, c: Cell) -> Cell {
        Cell::new(c.x.wrapping_sub(self.x0), c.y.wrapping_sub(self.y0))
    }
}

/// A resumable search on a window of a larger grid; cells in and out are
/// the larger grid's.
pub struct WindowSearch<const N: usize, const NW: usize> {
    /// The window's obstacles (a copy, taken at [`WindowSearch::begin`]).
    grid: Grid<NW>,
    /// The lent state's [`SearchState::query_id`] after this query began.
    query: u32,
    win: Window,
    /// The current query's goals, on the larger grid.
    goals: [Cell; MAX_GOALS],
    goal_count: usize,
    whole: bool,
    /// Block side of a [`WindowSearch::begin_blocks`] query (1 otherwise).
    block: u16,
    /// The larger grid's last cell (block centres are clamped to it).
    last: (u16, u16),
}

impl<const N: usize, const NW: usize> Default for WindowSearch<N, NW> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, const NW: usize> WindowSearch<N, NW> {
    /// The square window's side, cells (when the grid does not fit whole).
    pub const SIDE: u16 = {
        let s = isqrt_u64(N as u64);
        if s > u16::MAX as u64 {
            u16::MAX
        } else {
            s as u16
        }
    };

    /// An idle search (usable in a `static`; all-zero bytes are this
    /// state, as for [`SearchState`]).
    pub const fn new() -> Self {
        Self {
            grid: Grid::new(),
            query: 0,
            win: Window {
                x0: 0,
                y0: 0,
                w: 0,
                h: 0,
            },
            goals: [Cell::new(0, 0); MAX_GOALS],
            goal_count: 0,
            whole: false,
            block: 1,
            last: (0, 0),
        }
    }

    /// Starts a query on `big` from `start` to the nearest of `goals`
    /// (go on with [`WindowSearch::resume`]). Goals outside the window are
    /// left out; none inside is [`SearchError::OutOfWindow`]. `state` is
    /// lent for the query's duration (see the module docs).
    pub fn begin<const OPEN: usize, const GW: usize>(
        &mut self,
        state: &mut SearchState<N, NW, OPEN>,
        big: &Grid<GW>,
        start: Cell,
        goals: &[Cell],
        algo: Algo,
    ) -> Result<(), SearchError> {
        self.goal_count = 0;
        self.block = 1;
        if goals.len() > MAX_GOALS {
            return Err(SearchError::TooManyGoals);
        }
        if !big.contains(start.x as i32, start.y as i32) {
            return Err(SearchError::StartOffMap);
        }
        self.win = self.place(big, start, goals);
        self.copy_window(big)?;
        let mut local = [Cell::new(0, 0); MAX_GOALS];
        let whole = self.covers(big);
        self.whole = whole;
        for &g in goals {
            let (Some(l), Some(k)) = (
                local.get_mut(self.goal_count),
                self.goals.get_mut(self.goal_count),
            ) else {
                break;
            };
            // The whole grid: every goal as given (off-map goals fail in
            // the search, as they would on the grid itself).
            if whole || self.win.contains(g) {
                *l = self.win.local(g);
                *k = g;
                self.goal_count += 1;
            }
        }
        if self.goal_count == 0 && !goals.is_empty() {
            return Err(SearchError::OutOfWindow);
        }
        let local = local.get(..self.goal_count).unwrap_or(&[]);
        let r = state.begin(&self.grid, self.win.local(start), local, algo);
        self.query = state.query_id();
        r
    }

    /// Goes on with the query for at most `budget` node expansions, on the
    /// state lent to `begin`.
    pub fn resume<const OPEN: usize>(
        &mut self,
        state: &mut SearchState<N, NW, OPEN>,
        budget: u32,
    ) -> Result<Progress, SearchError> {
        self.check(state)?;
        state.resume(&self.grid, budget)
    }

    /// [`SearchError::Preempted`] when `state` no longer holds this query.
    fn check<const OPEN: usize>(
        &self,
        state: &SearchState<N, NW, OPEN>,
    ) -> Result<(), SearchError> {
        if state.query_id() == self.query {
            Ok(())
        } else {
            Err(SearchError::Preempted)
        }
    }

    /// Starts a query over the whole of `big` seen in blocks of `b × b`
    /// cells, `b` the smallest that fits the blocks in `N` cells: the long
    /// way between two cells of a grid too large for a window. A block is
    /// free when any of its cells is: a doorway stays open, and a wall
    /// (inflated by the robot's radius: at least one whole block thick
    /// when `b` cells are at most the robot's diameter) stays closed. The
    /// path ([`WindowSearch::write_path`]) is the blocks' centre cells,
    /// which the caller must check on `big` (a centre may be blocked).
    /// The blocks in `closed` (block coordinates) are closed whatever
    /// their cells: steps the caller found do not meet on `big`
    /// ([`super::blocks::blocks_connected`]).
    pub fn begin_blocks<const OPEN: usize, const GW: usize>(
        &mut self,
        state: &mut SearchState<N, NW, OPEN>,
        big: &Grid<GW>,
        (start, goal): (Cell, Cell),
        closed: &[Cell],
        algo: Algo,
    ) -> Result<(), SearchError> {
        self.goal_count = 0;
        let (bw, bh) = (big.width(), big.height());
        let mut b = 1u32;
        while (bw.div_ceil(b) as usize) * (bh.div_ceil(b) as usize) > N && b < u16::MAX as u32 {
            b += 1;
        }
        let (w, h) = (bw.div_ceil(b), bh.div_ceil(b));
        self.grid
            .reset(w, h)
            .map_err(|_| SearchError::MapTooLarge)?;
        for y in 0..h as i32 {
            for x in 0..w as i32 {
                if !any_free(big, x * b as i32, y * b as i32, b as i32) {
                    let _ = self.grid.set_obstacle(x, y, true);
                }
            }
        }
        for c in closed {
            let _ = self.grid.set_obstacle(c.x as i32, c.y as i32, true);
        }
        self.win = Window {
            x0: 0,
            y0: 0,
            w: w as u16,
            h: h as u16,
        };
        self.whole = false;
        self.block = b as u16;
        self.last = (bw.saturating_sub(1) as u16, bh.saturating_sub(1) as u16);
        let bs = (b as u16).max(1);
        let (s, g) = (
            Cell::new(start.x / bs, start.y / bs),
            Cell::new(goal.x / bs, goal.y / bs),
        );
        if let Some(k) = self.goals.get_mut(0) {
            *k = goal;
            self.goal_count = 1;
        }
        let r = state.begin(&self.grid, s, &[g], algo);
        self.query = state.query_id();
        r
    }

    /// Writes the found path (larger-grid cells, start first) into `out`;
    /// returns its length.
    pub fn write_path<const OPEN: usize>(
        &self,
        state: &SearchState<N, NW, OPEN>,
        out: &mut [Cell],
    ) -> Result<usize, SearchError> {
        self.check(state)?;
        let n = state.write_path(out)?;
        let b = self.block.max(1);
        for c in out.iter_mut().take(n) {
            *c = if b == 1 {
                Cell::new(c.x + self.win.x0, c.y + self.win.y0)
            } else {
                Cell::new(
                    (c.x * b + b / 2).min(self.last.0),
                    (c.y * b + b / 2).min(self.last.1),
                )
            };
        }
        Ok(n)
    }

    /// The current query's goals (those inside the window), larger-grid
    /// cells.
    pub fn goals(&self) -> &[Cell] {
        self.goals.get(..self.goal_count).unwrap_or(&[])
    }

    /// Block side of the current query (1 unless it is in blocks).
    pub fn block_side(&self) -> u16 {
        self.block.max(1)
    }

    /// The current query's window.
    pub fn window(&self) -> Window {
        self.win
    }

    fn covers<const GW: usize>(&self, big: &Grid<GW>) -> bool {
        self.win.x0 == 0
            && self.win.y0 == 0
            && self.win.w as u32 == big.width()
            && self.win.h as u32 == big.height()
    }

    /// True when the current query's window is the whole grid it was
    /// taken from (a failed search then means there is no way at all).
    pub fn is_whole(&self) -> bool {
        self.whole
    }

    /// Where the window lies on `big` (see the module docs).
    fn place<const GW: usize>(&self, big: &Grid<GW>, start: Cell, goals: &[Cell]) -> Window {
        let (bw, bh) = (big.width(), big.height());
        if (bw as usize) * (bh as usize) <= N {
            return Window {
                x0: 0,
                y0: 0,
                w: bw as u16,
                h: bh as u16,
            };
        }
        let side = Self::SIDE as u32;
        let (w, h) = (bw.min(side), bh.min(side));
        let (mut lo, mut hi) = ((start.x, start.y), (start.x, start.y));
        for g in goals {
            lo = (lo.0.min(g.x), lo.1.min(g.y));
            hi = (hi.0.max(g.x), hi.1.max(g.y));
        }
        let span = ((hi.0 - lo.0) as u32, (hi.1 - lo.1) as u32);
        // The box centred (its slack split evenly), or the start centred.
        let (x0, y0) = if span.0 < w && span.1 < h {
            (
                (lo.0 as u32).saturating_sub((w - 1 - span.0) / 2),
                (lo.1 as u32).saturating_sub((h - 1 - span.1) / 2),
            )
        } else {
            (
                (start.x as u32).saturating_sub(w / 2),
                (start.y as u32).saturating_sub(h / 2),
            )
        };
        Window {
            x0: x0.min(bw - w) as u16,
            y0: y0.min(bh - h) as u16,
            w: w as u16,
            h: h as u16,
        }
    }

    /// Copies the obstacles inside the window from `big`.
    fn copy_window<const GW: usize>(&mut self, big: &Grid<GW>) -> Result<(), SearchError> {
        let Window { x0, y0, w, h } = self.win;
        self.grid
            .reset(w as u32, h as u32)
            .map_err(|_| SearchError::MapTooLarge)?;
        for y in 0..h as i32 {
            for x in 0..w as i32 {
                if big.is_blocked(x + x0 as i32, y + y0 as i32) {
                    let _ = self.grid.set_obstacle(x, y, true);
                }
            }
        }
        Ok(())
    }
}

/// True when any cell of the `b × b` block at (x0, y0) of `g` is free.
fn any_free<const GW: usize>(g: &Grid<GW>, x0: i32, y0: i32, b: i32) -> bool {
    (y0..y0 + b).any(|y| (x0..x0 + b).any(|x| g.is_free(x, y)))
}
