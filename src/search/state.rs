//! The search state and its types: a leaf of the search layer. The loop
//! that drives it is [`super::run`]; the heuristics [`super::heuristics`].
//!
//! Memory is fixed by three const generics: `N` cells of g-score and parent
//! (4 + 4 bytes each), `NW` words of the closed and seen bitsets (N / 32,
//! checked at compile time), and `OPEN` entries of the open list (12 bytes
//! each). Nothing is allocated. Only the bitsets are cleared per query, so a
//! query on a small map in a big state costs nothing extra.

use super::open_list::OpenList;
use crate::grid::{Cell, Grid};
use crate::math::bits::Bits;
use crate::math::divide::{RowDivider, EXACT_BELOW};

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
    /// A* with the integer octile heuristic: the exact distance on an
    /// empty 8-connected grid, so admissible and consistent (optimal) and
    /// far tighter than the Euclidean one, with no square root. The
    /// Euclidean [`Algo::AStar`] stays for seed 000's Table 1 protocol.
    AStarOctile,
    /// Breadth-first search (seed 004's baseline): cells in the order they
    /// are discovered, each keeping its first parent. The path has the
    /// fewest moves, not the least cost (a diagonal counts as one move).
    Bfs,
    /// Depth-first search (seed 004's baseline): the newest discovered
    /// cell first, each keeping its first parent. It finds a path whenever
    /// one exists, usually a long one.
    Dfs,
    /// Jump point search ([`super::jps`]): [`Algo::AStarOctile`]'s costs
    /// and heuristic, with only the jump points pushed. Optimal; the
    /// fastest on open rooms and corridors.
    Jps,
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
    /// The shared search state was lent to another query since this one
    /// began ([`super::window::WindowSearch`]): begin it again.
    Preempted,
    /// `resume` without a `begin`, or after the query ended.
    NotRunning,
    /// The output buffer is shorter than the path.
    PathBufferTooSmall,
    /// No goal lies in a search window around the start
    /// ([`super::window::WindowSearch`]): route on a coarser grid first.
    OutOfWindow,
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
            SearchError::Preempted => "the shared search state was taken by another query",
            SearchError::NotRunning => "no search is running",
            SearchError::PathBufferTooSmall => "path buffer too small",
            SearchError::OutOfWindow => "no goal within the search window",
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
    /// Path cost in cost units ([`crate::math::cost::COST_PER_CELL`] per cell).
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

/// Checks a query's start, as every search does: on the map and free.
/// Returns its linear index.
pub(crate) fn check_start<const GW: usize>(
    grid: &Grid<GW>,
    start: Cell,
) -> Result<usize, SearchError> {
    check_end(
        grid,
        start,
        SearchError::StartOffMap,
        SearchError::StartBlocked,
    )
}

/// Checks a query's goal, as every search does: on the map and free.
pub(crate) fn check_goal<const GW: usize>(
    grid: &Grid<GW>,
    goal: Cell,
) -> Result<usize, SearchError> {
    check_end(
        grid,
        goal,
        SearchError::GoalOffMap,
        SearchError::GoalBlocked,
    )
}

/// Checks one end of a query: on the map (else `off`) and free (else
/// `blocked`). Returns its linear index.
fn check_end<const GW: usize>(
    grid: &Grid<GW>,
    end: Cell,
    off: SearchError,
    blocked: SearchError,
) -> Result<usize, SearchError> {
    let (x, y) = end.xy();
    let i = grid.index(x, y).ok_or(off)?;
    if grid.blocked_at(i) {
        return Err(blocked);
    }
    Ok(i)
}

pub(super) const IDLE: u8 = 0;
pub(super) const RUNNING: u8 = 1;
pub(super) const FOUND: u8 = 2;

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

/// A cell's search record: its cost so far and the linear index of its
/// parent.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Node {
    pub(super) g: u32,
    pub(super) parent: u32,
}

/// Search state for maps of up to `N` cells. `NW` must be `N / 32` rounded
/// up (checked at compile time); `OPEN` is the open list's capacity.
///
/// Every field is a plain integer (or array of them, or a `#[repr(u8)]`
/// enum whose discriminant 0 is a variant) and the all-zero bit pattern is
/// a valid idle state that behaves as [`SearchState::new`] (the dial's
/// list ends, which differ, are set by every `begin`); a host may therefore
/// allocate a large state directly on the heap, zeroed.
pub struct SearchState<const N: usize, const NW: usize, const OPEN: usize> {
    /// Each cell's g-score and parent side by side: relaxing a cell writes
    /// both, one cache line instead of two.
    pub(super) node: [Node; N],
    pub(super) seen: Bits<NW>,
    pub(super) closed: Bits<NW>,
    pub(super) open: OpenList<OPEN>,
    pub(super) goals: [Cell; MAX_GOALS],
    pub(super) goal_count: u32,
    /// The first goal's linear index: the goal test of a single-goal
    /// query is one compare.
    pub(super) goal_index: u32,
    pub(super) start: Cell,
    pub(super) algo: Algo,
    pub(super) phase: u8,
    pub(super) found: u32,
    pub(super) width: u32,
    pub(super) height: u32,
    /// Divides a linear index by `width` without a divide instruction.
    pub(super) rows: RowDivider,
    /// The linear index step to each neighbour, in the order of
    /// [`NEIGHBOURS`] (set by `begin` from the width).
    pub(super) steps: [i32; 8],
    pub(super) nodes: u32,
    /// Bumped by every `begin`: a caller that lends this state to another
    /// (the planner to the fine searches, [`super::window`]) compares it
    /// with the value its own `begin` left, to know whether its query was
    /// overwritten meanwhile.
    pub(super) query: u32,
    /// Pushes since `begin`: the order key of [`Algo::Bfs`] and
    /// [`Algo::Dfs`].
    pub(super) pushes: u32,
}

impl<const N: usize, const NW: usize, const OPEN: usize> Default for SearchState<N, NW, OPEN> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, const NW: usize, const OPEN: usize> SearchState<N, NW, OPEN> {
    const WORDS_OK: () = assert!(
        NW * 32 >= N && NW <= N / 32 + 1 && N <= EXACT_BELOW,
        "NW must be words_for(N), and N at most 2^24 (RowDivider)"
    );

    /// A fresh state (usable in a `static`).
    pub const fn new() -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::WORDS_OK;
        Self {
            node: [Node { g: 0, parent: 0 }; N],
            seen: Bits::new(),
            closed: Bits::new(),
            open: OpenList::new(),
            goals: [Cell::new(0, 0); MAX_GOALS],
            goal_count: 0,
            goal_index: 0,
            start: Cell::new(0, 0),
            algo: Algo::AStar,
            phase: IDLE,
            found: 0,
            width: 0,
            height: 0,
            rows: RowDivider::new(1),
            steps: [0; 8],
            nodes: 0,
            query: 0,
            pushes: 0,
        }
    }
    /// The goals of the current query.
    pub fn goals(&self) -> &[Cell] {
        self.goals.get(..self.goal_count as usize).unwrap_or(&[])
    }

    #[inline]
    pub(crate) fn g_at(&self, i: usize) -> u32 {
        self.node.get(i).map_or(u32::MAX, |n| n.g)
    }

    #[inline]
    pub(crate) fn parent_at(&self, i: usize) -> usize {
        self.node.get(i).map_or(i, |n| n.parent as usize)
    }

    pub(super) fn set_node(&mut self, i: usize, g: u32, parent: u32) {
        if let Some(n) = self.node.get_mut(i) {
            *n = Node { g, parent };
            self.seen.put(i, true);
        }
    }

    /// The cell at linear index `i` of the current map.
    #[inline(always)]
    pub(super) fn cell_of(&self, i: usize) -> Cell {
        let y = self.rows.div(i as u32);
        let x = (i as u32).wrapping_sub(y.wrapping_mul(self.width));
        Cell::new(x as u16, y as u16)
    }

    pub(crate) fn start_index(&self) -> usize {
        self.start.y as usize * self.width as usize + self.start.x as usize
    }

    pub(super) fn stats(&self, goal_idx: u32) -> SearchStats {
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

    pub(super) fn path_len(&self, goal_idx: usize) -> usize {
        let s = self.start_index();
        let mut i = goal_idx;
        let mut n = 1usize;
        let jumps = self.jumps();
        while i != s && n <= N {
            let p = self.parent_at(i);
            n += if jumps { self.gap(i, p) } else { 1 };
            i = p;
        }
        n
    }

    /// The cells from jump point `i` ([`Algo::Jps`]) toward its parent
    /// `p`, `i` included and `p` not: the steps of the straight or
    /// diagonal line between them (1 for the start, its own parent).
    fn gap(&self, i: usize, p: usize) -> usize {
        let ((x, y), (px, py)) = (self.cell_of(i).xy(), self.cell_of(p).xy());
        ((x - px).abs().max((y - py).abs()) as usize).max(1)
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
        let mut i = gi;
        let mut k = n;
        while k > 0 {
            let p = self.parent_at(i);
            let (x, y) = self.cell_of(i).xy();
            let (px, py) = self.cell_of(p).xy();
            let (sx, sy) = ((px - x).signum(), (py - y).signum());
            let gap = if self.jumps() { self.gap(i, p) } else { 1 };
            for s in 0..gap.min(k) as i32 {
                k -= 1;
                if let Some(slot) = out.get_mut(k) {
                    *slot = Cell::new((x + s * sx) as u16, (y + s * sy) as u16);
                }
            }
            i = p;
        }
        Ok(n)
    }

    /// Nodes expanded by the current or last query.
    pub fn nodes_expanded(&self) -> u32 {
        self.nodes
    }

    /// Which query the state holds: changes at every `begin` (wrapping), so
    /// a query's owner can tell whether the state it lent out still holds
    /// its query.
    pub fn query_id(&self) -> u32 {
        self.query
    }
}
