//! The shared best-first search machinery behind A*, OHA* and Theta*.
//!
//! One loop serves every algorithm; they differ only in the heuristic
//! ([`crate::astar`], [`crate::oha`]) and, for Theta*, in the parent update
//! ([`crate::theta_star`]). The search is 8-connected with octile step costs
//! and **no corner cutting**: a diagonal step needs both orthogonal
//! neighbours free. It is multi-goal: it stops at the first goal it closes,
//! with the heuristic taken as the minimum over the goals (ALGORITHMS.md §1,
//! eq. 4).
//!
//! Memory is fixed by three const generics: `N` cells of g-score and parent
//! (4 + 4 bytes each), `NW` words of the closed and seen bitsets (N / 32,
//! checked at compile time), and `OPEN` entries of the open list (12 bytes
//! each). Nothing is allocated. Only the bitsets are cleared per query, so a
//! query on a small map in a big state costs nothing extra.
//!
//! The search is **resumable**: [`SearchState::begin`] sets up a query and
//! [`SearchState::resume`] expands at most a given number of nodes per call,
//! so the firmware can bound the time of each control-loop tick.
//! [`SearchState::search`] runs a query to completion.

use crate::bits::Bits;
use crate::cost::{COST_DIAGONAL, COST_PER_CELL};
use crate::grid::{Cell, Grid};
use crate::open_list::{Entry, OpenList};
use crate::{astar, oha, theta_star};

/// The most goals one multi-goal query takes.
pub const MAX_GOALS: usize = 64;

/// Which search to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Algo {
    /// A* with the Euclidean heuristic (the paper's "traditional A*").
    AStar = 0,
    /// OHA*: A* with the orientation-weighted heuristic (2 + cos θ)·h.
    Oha,
    /// Theta*: any-angle A* (parents may be any visible cell).
    Theta,
}

/// Why a search failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SearchError {
    /// The start is off the map.
    StartOffMap,
    /// The start is an obstacle.
    StartBlocked,
    /// A goal is off the map.
    GoalOffMap,
    /// A goal is an obstacle.
    GoalBlocked,
    /// No goals were given.
    NoGoals,
    /// More than [`MAX_GOALS`] goals were given.
    TooManyGoals,
    /// No goal is reachable from the start.
    NoPath,
    /// The open list filled up (raise its `OPEN` capacity).
    OpenListFull,
    /// The map has more cells than the search state's `N`.
    MapTooLarge,
    /// The map was resized while a resumable search was running.
    MapChanged,
    /// `resume` without a `begin`, or after the query ended.
    NotRunning,
    /// The output buffer is shorter than the path.
    PathBufferTooSmall,
}

impl SearchError {
    /// A short human-readable description.
    pub const fn as_str(self) -> &'static str {
        match self {
            SearchError::StartOffMap => "start is off the map",
            SearchError::StartBlocked => "start is an obstacle",
            SearchError::GoalOffMap => "goal is off the map",
            SearchError::GoalBlocked => "goal is an obstacle",
            SearchError::NoGoals => "no goals given",
            SearchError::TooManyGoals => "too many goals",
            SearchError::NoPath => "no path between start and goal",
            SearchError::OpenListFull => "open list capacity exceeded",
            SearchError::MapTooLarge => "map exceeds the search capacity",
            SearchError::MapChanged => "map was resized during the search",
            SearchError::NotRunning => "no search is running",
            SearchError::PathBufferTooSmall => "path buffer too small",
        }
    }
}

impl core::fmt::Display for SearchError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What a finished search found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SearchStats {
    /// The goal reached.
    pub goal: Cell,
    /// Path cost in cost units ([`crate::cost::COST_PER_CELL`] per cell).
    pub cost: u32,
    /// Nodes expanded (closed), summed over every `resume` call.
    pub nodes_expanded: u32,
    /// Cells on the path, start and goal included.
    pub path_cells: u32,
    /// The open list's peak size.
    pub open_peak: u32,
}

/// Result of one bounded `resume` call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Progress {
    /// The search finished; the path can be read out.
    Found(SearchStats),
    /// The node budget ran out; call `resume` again.
    Pending {
        /// Nodes expanded so far.
        nodes_expanded: u32,
    },
}

const IDLE: u8 = 0;
const RUNNING: u8 = 1;
const FOUND: u8 = 2;

/// The 8 neighbour offsets: E, NE, N, NW, W, SW, S, SE (y grows downward,
/// so "N" is −y), matching S1..S8 of ALGORITHMS.md.
pub const NEIGHBOURS: [(i32, i32); 8] = [
    (1, 0),
    (1, -1),
    (0, -1),
    (-1, -1),
    (-1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// Search state for maps of up to `N` cells. `NW` must be `N / 32` rounded
/// up (checked at compile time); `OPEN` is the open list's capacity.
///
/// Every field is a plain integer (or array of them) and the all-zero bit
/// pattern is a valid idle state, equal to [`SearchState::new`]; a host
/// may therefore allocate a large state directly on the heap, zeroed.
pub struct SearchState<const N: usize, const NW: usize, const OPEN: usize> {
    g: [u32; N],
    parent: [u32; N],
    seen: Bits<NW>,
    closed: Bits<NW>,
    open: OpenList<OPEN>,
    goals: [Cell; MAX_GOALS],
    goal_count: u32,
    start: Cell,
    algo: Algo,
    phase: u8,
    found: u32,
    width: u32,
    height: u32,
    nodes: u32,
}

impl<const N: usize, const NW: usize, const OPEN: usize> Default for SearchState<N, NW, OPEN> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, const NW: usize, const OPEN: usize> SearchState<N, NW, OPEN> {
    const WORDS_OK: () = assert!(NW * 32 >= N && NW <= N / 32 + 1, "NW must be words_for(N)");

    /// A fresh state (usable in a `static`).
    pub const fn new() -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::WORDS_OK;
        Self {
            g: [0; N],
            parent: [0; N],
            seen: Bits::new(),
            closed: Bits::new(),
            open: OpenList::new(),
            goals: [Cell::new(0, 0); MAX_GOALS],
            goal_count: 0,
            start: Cell::new(0, 0),
            algo: Algo::AStar,
            phase: IDLE,
            found: 0,
            width: 0,
            height: 0,
            nodes: 0,
        }
    }

    /// Runs a whole query: the path from `start` to the nearest-found of
    /// `goals`. Read it with [`SearchState::write_path`].
    pub fn search<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        start: Cell,
        goals: &[Cell],
        algo: Algo,
    ) -> Result<SearchStats, SearchError> {
        self.begin(grid, start, goals, algo)?;
        match self.resume(grid, u32::MAX)? {
            Progress::Found(s) => Ok(s),
            // Unreachable with an unlimited budget, but never panic.
            Progress::Pending { .. } => Err(SearchError::NotRunning),
        }
    }

    /// Sets up a query without expanding anything.
    pub fn begin<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        start: Cell,
        goals: &[Cell],
        algo: Algo,
    ) -> Result<(), SearchError> {
        self.phase = IDLE;
        let cells = grid.cells();
        if cells > N || cells > NW * 32 {
            return Err(SearchError::MapTooLarge);
        }
        let (sx, sy) = start.xy();
        let si = grid.index(sx, sy).ok_or(SearchError::StartOffMap)?;
        if grid.blocked_at(si) {
            return Err(SearchError::StartBlocked);
        }
        if goals.is_empty() {
            return Err(SearchError::NoGoals);
        }
        if goals.len() > MAX_GOALS {
            return Err(SearchError::TooManyGoals);
        }
        for (slot, &goal) in self.goals.iter_mut().zip(goals) {
            let (gx, gy) = goal.xy();
            let gi = grid.index(gx, gy).ok_or(SearchError::GoalOffMap)?;
            if grid.blocked_at(gi) {
                return Err(SearchError::GoalBlocked);
            }
            *slot = goal;
        }
        self.goal_count = goals.len() as u32;
        self.start = start;
        self.algo = algo;
        self.width = grid.width();
        self.height = grid.height();
        self.nodes = 0;
        self.seen.clear_prefix(cells);
        self.closed.clear_prefix(cells);
        self.open.clear();
        self.set_node(si, 0, si as u32);
        let h = self.heuristic(start);
        self.open
            .push(Entry {
                f: h,
                g: 0,
                idx: si as u32,
            })
            .map_err(|_| SearchError::OpenListFull)?;
        self.phase = RUNNING;
        Ok(())
    }

    /// Expands at most `budget` nodes. The grid must be the one given to
    /// `begin` (obstacles may have changed; its size may not).
    pub fn resume<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        budget: u32,
    ) -> Result<Progress, SearchError> {
        match self.phase {
            RUNNING => {}
            FOUND => return Ok(Progress::Found(self.stats(self.found))),
            _ => return Err(SearchError::NotRunning),
        }
        if grid.width() != self.width || grid.height() != self.height {
            self.phase = IDLE;
            return Err(SearchError::MapChanged);
        }
        let mut left = budget;
        while left > 0 {
            let Some(e) = self.open.pop() else {
                self.phase = IDLE;
                return Err(SearchError::NoPath);
            };
            let i = e.idx as usize;
            if self.closed.get(i) {
                continue; // stale duplicate (lazy deletion)
            }
            self.closed.put(i, true);
            self.nodes = self.nodes.saturating_add(1);
            left -= 1;
            let cell = grid.cell_at(i);
            if self.goals().contains(&cell) {
                self.phase = FOUND;
                self.found = e.idx;
                return Ok(Progress::Found(self.stats(e.idx)));
            }
            if let Err(err) = self.expand(grid, i, cell) {
                self.phase = IDLE;
                return Err(err);
            }
        }
        Ok(Progress::Pending {
            nodes_expanded: self.nodes,
        })
    }

    fn expand<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        i: usize,
        cell: Cell,
    ) -> Result<(), SearchError> {
        let (x, y) = cell.xy();
        let gs = self.g_at(i);
        let w = self.width as usize;
        for (k, &(dx, dy)) in NEIGHBOURS.iter().enumerate() {
            let (nx, ny) = (x + dx, y + dy);
            if !grid.contains(nx, ny) {
                continue;
            }
            let ni = ny as usize * w + nx as usize;
            if grid.blocked_at(ni) || self.closed.get(ni) {
                continue;
            }
            let diagonal = k % 2 == 1;
            if diagonal && (grid.is_blocked(x + dx, y) || grid.is_blocked(x, y + dy)) {
                continue; // no corner cutting
            }
            let step = if diagonal {
                COST_DIAGONAL
            } else {
                COST_PER_CELL
            };
            let (cand, par) = match self.algo {
                Algo::Theta => theta_star::relax(self, grid, i, gs, (nx, ny), step),
                Algo::AStar | Algo::Oha => (gs.saturating_add(step), i as u32),
            };
            if !self.seen.get(ni) || cand < self.g_at(ni) {
                self.set_node(ni, cand, par);
                let h = self.heuristic(Cell::new(nx as u16, ny as u16));
                self.open
                    .push(Entry {
                        f: cand.saturating_add(h),
                        g: cand,
                        idx: ni as u32,
                    })
                    .map_err(|_| SearchError::OpenListFull)?;
            }
        }
        Ok(())
    }

    fn heuristic(&self, s: Cell) -> u32 {
        match self.algo {
            Algo::AStar | Algo::Theta => astar::heuristic(s, self.goals()),
            Algo::Oha => oha::heuristic(s, self.start, self.goals()),
        }
    }

    /// The goals of the current query.
    pub fn goals(&self) -> &[Cell] {
        self.goals.get(..self.goal_count as usize).unwrap_or(&[])
    }

    #[inline]
    pub(crate) fn g_at(&self, i: usize) -> u32 {
        self.g.get(i).copied().unwrap_or(u32::MAX)
    }

    #[inline]
    pub(crate) fn parent_at(&self, i: usize) -> usize {
        self.parent.get(i).map(|&p| p as usize).unwrap_or(i)
    }

    fn set_node(&mut self, i: usize, g: u32, parent: u32) {
        if let (Some(gs), Some(ps)) = (self.g.get_mut(i), self.parent.get_mut(i)) {
            *gs = g;
            *ps = parent;
            self.seen.put(i, true);
        }
    }

    pub(crate) fn start_index(&self) -> usize {
        self.start.y as usize * self.width as usize + self.start.x as usize
    }

    fn stats(&self, goal_idx: u32) -> SearchStats {
        let gi = goal_idx as usize;
        let w = (self.width as usize).max(1);
        SearchStats {
            goal: Cell::new((gi % w) as u16, (gi / w) as u16),
            cost: self.g_at(gi),
            nodes_expanded: self.nodes,
            path_cells: self.path_len(gi) as u32,
            open_peak: self.open.peak() as u32,
        }
    }

    fn path_len(&self, goal_idx: usize) -> usize {
        let s = self.start_index();
        let mut i = goal_idx;
        let mut n = 1usize;
        while i != s && n <= N {
            i = self.parent_at(i);
            n += 1;
        }
        n
    }

    /// Writes the found path, start first, into `out`; returns its length.
    pub fn write_path(&self, out: &mut [Cell]) -> Result<usize, SearchError> {
        if self.phase != FOUND {
            return Err(SearchError::NotRunning);
        }
        let gi = self.found as usize;
        let n = self.path_len(gi);
        if n > out.len() {
            return Err(SearchError::PathBufferTooSmall);
        }
        let w = (self.width as usize).max(1);
        let mut i = gi;
        for k in (0..n).rev() {
            if let Some(slot) = out.get_mut(k) {
                *slot = Cell::new((i % w) as u16, (i / w) as u16);
            }
            i = self.parent_at(i);
        }
        Ok(n)
    }

    /// Nodes expanded by the current or last query.
    pub fn nodes_expanded(&self) -> u32 {
        self.nodes
    }
}
