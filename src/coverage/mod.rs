//! The complete-coverage planner's shared machinery (seed 000 Algorithm 2
//! and its baselines): the online step loop, the bounded backtracking list,
//! transit search and following, and the completeness fallback.
//!
//! The planner is **online**: [`Coverage::step`] returns the next waypoint
//! to drive to, given the grid as known now, so the firmware calls it from
//! its control loop. A transit search is spread over calls with a node
//! budget per call ([`Step::Pending`] until it finishes); the batch planner
//! of the CLI is the same code driven to completion ([`Coverage::run`]).
//!
//! The planner marks the grid's `Covered` layer as the robot passes (the
//! cells of each segment's supercover line, the definition of
//! [`crate::verify::metrics`]), and reads obstacles afresh at every step: a cell
//! that turns into an obstacle, or one discovered later, is handled without
//! a restart (a blocked transit segment is re-planned; an unreachable goal
//! is abandoned).
//!
//! What differs between the planners — move priority, what enters the
//! backtracking list, how it is pruned, which goals a transit aims at and
//! with which search — lives in one file per planner under [`planners`]
//! ([`planners::b_oha`], [`planners::ba_star`], [`planners::b_theta`],
//! [`planners::b_oha_pc`]), each naming its [`rules::Rules`];
//! [`PlannerKind::rules`] is the one `match` on the planner kind.
//!
//! Files: [`cells`], [`list`] and [`rules`] are leaves; the planners use
//! them; this file, the loop, uses all of them. Uses `grid`, `search`,
//! `math` and `verify::metrics` (the segment kinds).
//!
//! **Entering a backtracking point is cleaning (our rule).** When the goal
//! of a transit is an uncovered cell (B-OHA*'s points always are), the
//! transit ends at the cell before it and the step into the goal is the
//! first cover move of the new segment. BA*'s points are covered cells next
//! to uncovered ones, and BA* then steps into the uncovered area as a cover
//! move; the rule gives every planner the same convention, so "backtracking
//! path length" means the same thing for all of them.
//!
//! **Segments.** A cover segment starts at the first move and after every
//! critical point; [`Waypoint::starts_segment`] marks it, so the paper's
//! "segments ≈ backtracks + 1" holds even when a backtracking point is a
//! neighbour and no transit is needed.
//!
//! **Bounded list and completeness (our policy).** The backtracking list has
//! a fixed capacity `LCAP`. A point that does not fit is dropped and the
//! overflow counted. Whenever the list runs empty, the planner **rescans**
//! the grid for uncovered free cells that are corners of their uncovered
//! region (the cells seed 000's pruning rule keeps) and refills the list.
//! Every uncovered region has such a cell (its top-left-most cell has no
//! uncovered neighbour to the north or west), so no reachable area is ever
//! silently missed, whatever the capacity and whatever the planner's own
//! list rule. Goals that a search proves unreachable are abandoned (an
//! enclosed pocket), so the run ends. The rescan costs O(cells) once per
//! emptied list.

pub mod cells;
mod kind;
pub mod list;
mod local;
pub mod planners;
pub mod rules;
pub mod types;
mod upkeep;

pub use cells::{nearest_k, uncovered, E_, N_, S_, W_};
pub use kind::PlannerKind;
pub use list::BacktrackList;
pub use types::{CoverageError, PlanStats, Step, Waypoint};

use crate::grid::los::line_of_sight;
use crate::grid::{Cell, Grid, Layer};
use crate::search::prune::prune;
use crate::search::{Progress, SearchError, SearchState, MAX_GOALS};
use crate::verify::metrics::SegmentKind;
use planners::{b_oha, ba_star, template};
use rules::{ListRule, Priority};

#[derive(Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Phase {
    Idle = 0,
    Local,
    Critical,
    Searching,
    Following,
    Done,
}

/// The coverage planner. `N`, `NW`, `OPEN` size its search state (see
/// [`SearchState`]), `LCAP` the backtracking list, `PCAP` the transit path
/// buffer, `F` the per-cell field of the planners that keep a value per
/// cell (wavefront, STC, BCD, regions: 2 bytes a cell; 0, the default, leaves them
/// out). All memory is inline; nothing is allocated.
///
/// Like [`SearchState`], every field is an integer, an array of integers or
/// a `#[repr(u8)]` enum whose discriminant 0 is a variant, so all-zero bytes
/// are a valid idle B-OHA* planner (a host may allocate one zeroed on the
/// heap and call [`Coverage::set_kind`]).
pub struct Coverage<
    const N: usize,
    const NW: usize,
    const OPEN: usize,
    const LCAP: usize,
    const PCAP: usize,
    const F: usize = 0,
> {
    kind: PlannerKind,
    search: SearchState<N, NW, OPEN>,
    list: BacktrackList<LCAP, NW>,
    path: [Cell; PCAP],
    path_len: usize,
    path_pos: usize,
    /// Index of the first cover waypoint of the followed path.
    transit_end: usize,
    new_segment: bool,
    goals: [Cell; MAX_GOALS],
    goal_count: usize,
    cur: Cell,
    /// The direction of the last move, unit steps ((0, 0) before the
    /// first): seed 001's marks and BINN's turn term read it.
    heading: (i8, i8),
    priority: [(i32, i32); 4],
    phase: Phase,
    stats: PlanStats,
    last_step_nodes: u32,
    /// The search state's query id after this planner's last `begin`: a
    /// different one means the state was lent out meanwhile
    /// ([`Coverage::search_state_mut`]) and the transit search begins again.
    query: u32,
    /// Where the run started: the wavefront's goal.
    origin: Cell,
    /// The per-cell field: a distance transform, a spanning forest or the
    /// decomposition's labels, by planner.
    field: [u16; F],
}

impl<
        const N: usize,
        const NW: usize,
        const OPEN: usize,
        const LCAP: usize,
        const PCAP: usize,
        const F: usize,
    > Coverage<N, NW, OPEN, LCAP, PCAP, F>
{
    /// A planner of the given kind (usable in a `static`).
    pub const fn new(kind: PlannerKind) -> Self {
        Self {
            kind,
            search: SearchState::new(),
            list: BacktrackList::new(),
            path: [Cell::new(0, 0); PCAP],
            path_len: 0,
            path_pos: 0,
            transit_end: 0,
            new_segment: false,
            goals: [Cell::new(0, 0); MAX_GOALS],
            goal_count: 0,
            cur: Cell::new(0, 0),
            heading: (0, 0),
            priority: [N_, S_, E_, W_],
            phase: Phase::Idle,
            stats: PlanStats {
                backtrack_points_total: 0,
                backtrack_points_kept: 0,
                nodes_expanded: 0,
                critical_points: 0,
                searches: 0,
                rescans_with_points: 0,
                list_overflows: 0,
                abandoned_goals: 0,
                replans: 0,
            },
            last_step_nodes: 0,
            query: 0,
            origin: Cell::new(0, 0),
            field: [0; F],
        }
    }

    /// Changes the planner kind (takes effect at the next `start`).
    pub fn set_kind(&mut self, kind: PlannerKind) {
        self.kind = kind;
        self.phase = Phase::Idle;
    }

    /// Which planner this is.
    pub fn kind(&self) -> PlannerKind {
        self.kind
    }

    /// Nodes the last `step` call expanded (at most its budget).
    pub fn last_step_nodes(&self) -> u32 {
        self.last_step_nodes
    }

    /// Counters so far.
    pub fn stats(&self) -> PlanStats {
        PlanStats {
            backtrack_points_total: self.list.inserted(),
            list_overflows: self.list.overflows(),
            ..self.stats
        }
    }

    /// The planner's search state, lent for other queries (the mission's
    /// fine searches, point-to-point queries), so a firmware needs one
    /// search state, not two. Lending it during a transit search is safe:
    /// the planner sees the state's query id change and searches again
    /// from the start, so a caller that lent it at every step would starve
    /// it (the executive lends it only while the planner waits).
    pub fn search_state_mut(&mut self) -> &mut SearchState<N, NW, OPEN> {
        &mut self.search
    }

    /// The current backtracking list.
    pub fn backtrack_list(&self) -> &[Cell] {
        self.list.as_slice()
    }

    /// Takes up planning again after [`Step::Done`] (the caller cleared
    /// the covered mark of cells it could not clean): the next step
    /// rescans for uncovered cells. `cur` becomes `at`, where the robot
    /// will be.
    pub fn reopen(&mut self, at: Cell) {
        if self.phase == Phase::Done {
            self.phase = Phase::Critical;
            self.cur = at;
        }
    }

    /// Forgets every goal given up as unreachable, so the next rescan
    /// tries them again (the map may have opened: a person who stood in a
    /// doorway has walked on). Returns how many there were; with some, a
    /// finished planner takes up planning again from `at`.
    pub fn retry_abandoned(&mut self, at: Cell) -> u32 {
        let n = self.list.forget_abandoned();
        if n > 0 {
            self.reopen(at);
        }
        n
    }

    /// Puts a cell back on the backtracking list (a cell the caller
    /// un-covered because the robot could not clean it). False when the
    /// list is full.
    pub fn add_point<const GW: usize>(&mut self, grid: &Grid<GW>, c: Cell) -> bool {
        self.list.push(grid, c)
    }

    /// The robot's current cell as the planner sees it.
    pub fn position(&self) -> Cell {
        self.cur
    }

    /// Starts a run at `start`: clears the covered layer, marks the start
    /// covered and sets the move priority.
    pub fn start<const GW: usize>(
        &mut self,
        grid: &mut Grid<GW>,
        start: Cell,
    ) -> Result<(), CoverageError> {
        Self::check_start(grid, start)?;
        grid.clear_layer(Layer::Covered);
        self.start_keeping(grid, start)
    }

    /// A run can start at `start`: the grid fits, and the cell is free.
    fn check_start<const GW: usize>(grid: &Grid<GW>, start: Cell) -> Result<(), CoverageError> {
        let (x, y) = start.xy();
        if grid.cells() > N || grid.is_blocked(x, y) {
            return Err(CoverageError::BadStart);
        }
        Ok(())
    }

    /// Starts a run at `start` on a grid whose covered layer already
    /// holds what an earlier run cleaned (restored after a power loss,
    /// [`crate::robot::progress_image`]): only the rest is planned. The
    /// backtracking list starts empty; the planner's rescan of the grid
    /// when its list runs dry finds what is left.
    pub fn start_keeping<const GW: usize>(
        &mut self,
        grid: &mut Grid<GW>,
        start: Cell,
    ) -> Result<(), CoverageError> {
        Self::check_start(grid, start)?;
        if self.kind.rules().local.needs_field() && grid.cells() > F {
            return Err(CoverageError::NoField);
        }
        let (x, y) = start.xy();
        self.list.reset();
        self.path_len = 0;
        self.path_pos = 0;
        self.goal_count = 0;
        self.stats = PlanStats::default();
        self.cur = start;
        self.origin = start;
        self.heading = (0, 0);
        self.priority = match self.kind.rules().priority {
            Priority::ByAspect => b_oha::priority(grid),
            Priority::Fixed(p) => p,
        };
        let _ = grid.set(Layer::Covered, x, y, true);
        self.build_field(grid);
        self.on_arrive(grid);
        self.new_segment = true;
        self.phase = Phase::Local;
        Ok(())
    }

    /// Sweeps columns (`true`) or rows from here on, in place of the
    /// whole grid's aspect ratio, for planners whose priority follows it
    /// (B-OHA* §2.1 applied to one room by the mission; call it after
    /// `start`, which sets the grid's). Other planners keep their fixed
    /// order.
    pub fn sweep_columns(&mut self, columns: bool) {
        if self.kind.rules().priority == Priority::ByAspect {
            self.priority = b_oha::sweep_priority(columns);
        }
    }

    /// Runs to completion, calling `emit` for every waypoint (the batch
    /// planner of the CLI and the tests).
    pub fn run<const GW: usize>(
        &mut self,
        grid: &mut Grid<GW>,
        start: Cell,
        mut emit: impl FnMut(Waypoint),
    ) -> Result<PlanStats, CoverageError> {
        self.start(grid, start)?;
        loop {
            match self.step(grid, u32::MAX)? {
                Step::Done => return Ok(self.stats()),
                Step::Move(w) => emit(w),
                Step::Pending => {}
            }
        }
    }

    /// The next waypoint. A transit search expands at most `budget` nodes
    /// in this call; other work per call is one move, or at a critical point
    /// one pass over the list (and, when it runs empty, one over the grid).
    pub fn step<const GW: usize>(
        &mut self,
        grid: &mut Grid<GW>,
        budget: u32,
    ) -> Result<Step, CoverageError> {
        self.last_step_nodes = 0;
        // One budget for every search this call runs (a failed search may
        // be followed by another toward other goals).
        let mut left = budget;
        loop {
            let next = match self.phase {
                Phase::Idle => return Err(CoverageError::NotStarted),
                Phase::Done => return Ok(Step::Done),
                Phase::Local => self.local_step(grid),
                Phase::Critical => self.critical_step(grid)?,
                Phase::Searching if left == 0 => return Ok(Step::Pending),
                Phase::Searching => self.search_step(grid, &mut left)?,
                Phase::Following => self.follow_step(grid),
            };
            if let Some(step) = next {
                return Ok(step);
            }
        }
    }

    /// Local coverage: the next move, or at a critical point the list's
    /// pruning or rebuild.
    fn local_step<const GW: usize>(&mut self, grid: &mut Grid<GW>) -> Option<Step> {
        if let Some(next) = self.next_local_move(grid) {
            self.cover_segment(grid, next);
            self.cur = next;
            self.on_arrive(grid);
            return Some(self.emit(next, SegmentKind::Cover));
        }
        self.new_segment = true;
        self.phase = Phase::Critical;
        self.stats.critical_points += 1;
        match self.kind.rules().list {
            ListRule::NeighboursPrunedToCorners => b_oha::prune_list(&mut self.list, grid),
            ListRule::RebuiltFromCovered => ba_star::rebuild_list(&mut self.list, grid),
            ListRule::NeighboursPrunedToEdges => template::prune_list(&mut self.list, grid),
            ListRule::Marks | ListRule::RescanOnly => {}
        }
        self.stats.backtrack_points_kept += self.list.len() as u32;
        None
    }

    /// At a critical point: the goals of the next transit and its search,
    /// or done when nothing is left.
    fn critical_step<const GW: usize>(
        &mut self,
        grid: &mut Grid<GW>,
    ) -> Result<Option<Step>, CoverageError> {
        self.drop_stale(grid);
        if self.list.is_empty() {
            self.build_field(grid);
            self.rescan(grid);
        }
        if self.list.is_empty() {
            self.phase = Phase::Done;
            return Ok(Some(Step::Done));
        }
        let algo = self.choose_goals(grid);
        let goals = self.goals.get(..self.goal_count).unwrap_or(&[]);
        let begun = self.search.begin(grid, self.cur, goals, algo);
        self.query = self.search.query_id();
        begun.map_err(CoverageError::Search)?;
        self.stats.searches += 1;
        self.phase = Phase::Searching;
        Ok(None)
    }

    /// The transit search, within what is left of the budget; unreachable
    /// goals are abandoned.
    fn search_step<const GW: usize>(
        &mut self,
        grid: &mut Grid<GW>,
        left: &mut u32,
    ) -> Result<Option<Step>, CoverageError> {
        if self.search.query_id() != self.query {
            // The state was lent to another query: search again.
            self.phase = Phase::Critical;
            return Ok(None);
        }
        match self.resume_search(grid, left) {
            Ok(Progress::Pending { .. }) => return Ok(Some(Step::Pending)),
            Ok(Progress::Found(st)) => {
                self.stats.nodes_expanded += st.nodes_expanded as u64;
                let n = self
                    .search
                    .write_path(&mut self.path)
                    .map_err(|_| CoverageError::PathTooLong)?;
                self.split_path(grid, n);
                self.path_pos = 1;
                self.phase = Phase::Following;
            }
            Err(SearchError::NoPath) => {
                self.stats.nodes_expanded += self.search.nodes_expanded() as u64;
                for k in 0..self.goal_count {
                    if let Some(&g) = self.goals.get(k) {
                        self.abandon(grid, g);
                    }
                }
                self.phase = Phase::Critical;
            }
            Err(e) => return Err(CoverageError::Search(e)),
        }
        Ok(None)
    }

    /// The next waypoint of the transit path (re-planned when the grid
    /// changed under it); back to local coverage at its end.
    fn follow_step<const GW: usize>(&mut self, grid: &mut Grid<GW>) -> Option<Step> {
        let Some(&next) = self
            .path
            .get(self.path_pos)
            .filter(|_| self.path_pos < self.path_len)
        else {
            self.phase = Phase::Local;
            self.on_arrive(grid);
            return None;
        };
        if !line_of_sight(grid, self.cur, next) {
            // The grid changed under the planned path: re-plan.
            self.stats.replans += 1;
            self.phase = Phase::Critical;
            return None;
        }
        self.cover_segment(grid, next);
        self.cur = next;
        let kind = if self.path_pos < self.transit_end {
            SegmentKind::Transit
        } else {
            SegmentKind::Cover
        };
        self.path_pos += 1;
        Some(self.emit(next, kind))
    }

    /// Resumes the transit search within what is `left` of this call's
    /// budget, and charges what it used.
    fn resume_search<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        left: &mut u32,
    ) -> Result<Progress, SearchError> {
        let before = self.search.nodes_expanded();
        let r = self.search.resume(grid, *left);
        let used = self.search.nodes_expanded().saturating_sub(before);
        self.last_step_nodes += used;
        *left = left.saturating_sub(used);
        r
    }

    /// Makes the waypoint for a move, marking the first cover move of a
    /// segment.
    fn emit(&mut self, to: Cell, kind: SegmentKind) -> Step {
        let starts_segment = kind == SegmentKind::Cover && self.new_segment;
        if starts_segment {
            self.new_segment = false;
        }
        Step::Move(Waypoint {
            to,
            kind,
            starts_segment,
        })
    }

    /// Prepares the found path (`n` cells in `self.path`) for following:
    /// when the goal is uncovered, the transit ends at the cell before it
    /// and the last step is a cover move; the transit part is pruned
    /// (except for B-Theta*, whose any-angle path is followed as found).
    fn split_path<const GW: usize>(&mut self, grid: &Grid<GW>, n: usize) {
        let goal_uncovered = n >= 2
            && self
                .path
                .get(n - 1)
                .is_some_and(|c| !grid.get(Layer::Covered, c.x as i32, c.y as i32));
        let t = if goal_uncovered { n - 1 } else { n };
        let m = if self.kind.rules().prune_transit {
            prune(grid, self.path.get_mut(..t).unwrap_or(&mut []))
        } else {
            t
        };
        if let Some(cells) = self.path.get_mut(..n) {
            // The cover moves path[t..n] follow the pruned transit. The
            // guard proves copy_within's range checks away (the firmware
            // links no panicking branch).
            if m < t && t <= cells.len() {
                cells.copy_within(t.., m);
            }
        }
        // path[1..m] are transit waypoints, path[m..] cover moves.
        self.transit_end = m;
        self.path_len = m + (n - t);
    }
}
