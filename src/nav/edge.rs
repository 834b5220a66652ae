//! Edge cleaning: a pass along every wall and piece of furniture, after the
//! coverage planner's lanes. Ours, not from the papers: a grid coverage
//! plan puts the robot's centre on planning-cell centres, so along any wall
//! that does not fall on a cell boundary a strip up to one cell wide is
//! never swept. Real vacuums close it with an edge pass; so do we.
//!
//! On the fine configuration space ([`crate::nav::cspace::build_fine`]), the
//! boundary cells are the free cells reachable from the robot with a
//! blocked 4-neighbour: the positions closest to an obstacle the robot may
//! take. The pass walks them greedily, each step to an unvisited boundary
//! 8-neighbour as close as possible to the current direction (so it runs
//! along a contour), and when none is left it takes a multi-goal A*
//! transit to the nearest unvisited boundary cells. Diagonal steps never cut
//! a corner.
//!
//! Layers of the fine grid used: Obstacle (blocked positions; unreachable
//! free cells are blocked too once the reachability fill ends), Known
//! (reached by the fill; once it ends, reachable cells the robot's centre
//! has not passed: see [`EdgePass::driven`]), Covered (boundary cells visited, and
//! every cell the robot's centre passed).
//!
//! **Visited is not driven.** A cell the walk emits is marked visited at
//! once, but the robot may never drive it: the mission drops queued moves
//! when it plans a leg again (the guard held it, the map learnt a wall),
//! and gives cells back only so often. In unknown mode that lost whole
//! stretches of contour (1c home, realistic noise, 1 person, seed 4: 449
//! of the 808 missed floor cells within 15 cm of a wall lay beside a
//! contour cell marked visited that the robot's centre never came within
//! a cell of). So the mission reports where the centre went
//! ([`EdgePass::driven`]), and at [`EdgeStep::Done`] [`EdgePass::recheck`] hands the
//! visited cells it never came near back to the walk, [`RECHECKS`] times
//! per pass at most.
//!
//! Work per [`EdgePass::step`] call is bounded: one forward and one
//! backward sweep of the fill, or one move, or one scan of the grid for
//! goals, or `budget` search nodes.

use crate::grid::{Cell, Grid, Layer};
use crate::search::{Algo, Progress, SearchError, SearchState, WindowSearch};

/// Goals per transit search.
pub const EDGE_GOALS: usize = 16;

/// A transit search that found no way to its goals, having expanded fewer
/// than this share (1/n) of the cells the fill reached, was boxed in
/// rather than facing unreachable goals.
pub const BOXED_IN_SHARE: u32 = 4;

/// True when a failed transit search (`expanded` nodes) explored under
/// [`BOXED_IN_SHARE`]'s share of the `reached` cells: the robot's own
/// region shrank since the fill (a person beside it is mapped, or a
/// bump's mark closed it in). Its goals must then not be marked visited:
/// the covered layer outlives the pass (the lanes' track keeps it), so a
/// robot boxed in for a few seconds gave up every contour the searches
/// meanwhile aimed at (641 boundary cells in the l10su home, unknown mode,
/// realistic noise, 1 person, seed 1: 89 % covered). The caller builds
/// the pass again from a fresher map instead.
fn boxed_in(expanded: u32, reached: u32) -> bool {
    expanded.saturating_mul(BOXED_IN_SHARE) < reached
}

/// What to do next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EdgeStep {
    /// Drive to this fine cell; `edge` is true along a contour, false in a
    /// transit between contours.
    Move {
        /// The cell.
        to: Cell,
        /// Along a contour.
        edge: bool,
    },
    /// Work is under way (fill or search); call again.
    Pending,
    /// Every reachable boundary cell is visited.
    Done,
}

/// Counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EdgeStats {
    /// Reachable boundary cells visited.
    pub visited: u32,
    /// Transits between contours.
    pub transits: u32,
    /// Goals found unreachable.
    pub unreachable: u32,
    /// Fill sweeps.
    pub sweeps: u32,
    /// Free cells on the grid, and those reachable from the start (set
    /// when the fill ends).
    pub free: u32,
    /// Reachable free cells.
    pub reached: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Idle,
    Fill,
    Walk,
    Search,
    Transit,
    Done,
}

/// The edge pass's state (small; the grid, search state and path buffer
/// are the caller's).
#[derive(Clone, Debug)]
pub struct EdgePass {
    phase: Phase,
    last: Cell,
    dir: (i32, i32),
    path_len: usize,
    path_pos: usize,
    far_goal: Cell,
    rechecks: u8,
    /// Counters.
    pub stats: EdgeStats,
}

impl Default for EdgePass {
    fn default() -> Self {
        Self::new()
    }
}

/// Rounds of [`EdgePass::recheck`] per pass: the second catches what the
/// first round's own moves lost; a contour the robot cannot drive (a
/// person keeps standing there) is then left, so the pass ends.
pub const RECHECKS: u8 = 2;

/// Fine cell (x, y) is done with: driven, or given up. It counts as
/// visited, and the recheck leaves it.
fn done_with<const GW: usize>(fine: &mut Grid<GW>, x: i32, y: i32) {
    let _ = fine.set(Layer::Covered, x, y, true);
    let _ = fine.set(Layer::Known, x, y, false);
}

/// Every cell marked visited counts as driven (the lanes' track, a pass
/// begun before, a restored progress): clears their Known mark.
pub fn settle_driven<const GW: usize>(fine: &mut Grid<GW>) {
    let (w, h) = (fine.width() as i32, fine.height() as i32);
    for y in 0..h {
        for x in 0..w {
            if fine.get(Layer::Covered, x, y) {
                let _ = fine.set(Layer::Known, x, y, false);
            }
        }
    }
}

/// A boundary cell marked visited that the robot's centre never came
/// within one cell of (the chords stray up to 40 mm from the cells they
/// stand for, so a neighbour driven counts).
fn visited_not_driven<const GW: usize>(g: &Grid<GW>, x: i32, y: i32) -> bool {
    let undriven = |x: i32, y: i32| g.is_blocked(x, y) || g.get(Layer::Known, x, y);
    is_boundary(g, x, y)
        && g.get(Layer::Covered, x, y)
        && (-1..=1).all(|dy| (-1..=1).all(|dx| undriven(x + dx, y + dy)))
}

/// True when (x, y) is a free cell with a blocked 4-neighbour.
pub fn is_boundary<const GW: usize>(g: &Grid<GW>, x: i32, y: i32) -> bool {
    g.is_free(x, y)
        && [(1, 0), (-1, 0), (0, 1), (0, -1)]
            .iter()
            .any(|&(dx, dy)| g.is_blocked(x + dx, y + dy))
}

fn todo<const GW: usize>(g: &Grid<GW>, x: i32, y: i32) -> bool {
    is_boundary(g, x, y) && !g.get(Layer::Covered, x, y)
}

impl EdgePass {
    /// An idle pass.
    pub const fn new() -> Self {
        Self {
            phase: Phase::Idle,
            last: Cell::new(0, 0),
            dir: (0, 0),
            path_len: 0,
            path_pos: 0,
            far_goal: Cell::new(0, 0),
            rechecks: 0,
            stats: EdgeStats {
                visited: 0,
                transits: 0,
                unreachable: 0,
                sweeps: 0,
                free: 0,
                reached: 0,
            },
        }
    }

    /// Takes up the pass again after [`EdgeStep::Done`] (the caller
    /// cleared the visited mark of cells it could not drive), from `at`.
    pub fn reopen(&mut self, at: Cell) {
        if self.phase == Phase::Done {
            self.phase = Phase::Walk;
            self.last = at;
            self.dir = (0, 0);
        }
    }

    /// At [`EdgeStep::Done`], with every emitted move driven or dropped:
    /// the visited boundary cells the robot's centre never came near go
    /// back to the walk (see the module's doc), which goes on from where
    /// it stands. Returns how many; 0 after [`RECHECKS`] rounds.
    pub fn recheck<const GW: usize>(&mut self, fine: &mut Grid<GW>) -> u32 {
        if self.phase != Phase::Done || !self.rechecks_left() {
            return 0;
        }
        self.rechecks += 1;
        let (w, h) = (fine.width() as i32, fine.height() as i32);
        let mut n = 0u32;
        for y in 0..h {
            for x in 0..w {
                if visited_not_driven(fine, x, y) {
                    let _ = fine.set(Layer::Covered, x, y, false);
                    n += 1;
                }
            }
        }
        self.stats.visited = self.stats.visited.saturating_sub(n);
        if n > 0 {
            let at = self.last;
            self.reopen(at);
        }
        n
    }

    /// The robot's centre passed fine cell (x, y) (the mission's trace):
    /// it is driven, and counts as visited. During the fill, whose Known
    /// marks are the reached cells, only the visit is marked (the fill's
    /// end counts it driven).
    pub fn driven<const GW: usize>(&self, fine: &mut Grid<GW>, x: i32, y: i32) {
        if self.phase == Phase::Fill {
            let _ = fine.set(Layer::Covered, x, y, true);
        } else {
            done_with(fine, x, y);
        }
    }

    /// Rounds of [`EdgePass::recheck`] are left.
    pub fn rechecks_left(&self) -> bool {
        self.rechecks < RECHECKS
    }

    /// The last cell emitted.
    pub fn position(&self) -> Cell {
        self.last
    }

    /// The nearest unvisited boundary cell of the last walk's end: after
    /// [`SearchError::OutOfWindow`], where the caller should take the
    /// robot by a longer way before [`EdgePass::jump_to`].
    pub fn far_goal(&self) -> Cell {
        self.far_goal
    }

    /// Goes on from `at` (the caller took the robot there).
    pub fn jump_to(&mut self, at: Cell) {
        if self.phase != Phase::Done {
            self.phase = Phase::Walk;
            self.last = at;
            self.dir = (0, 0);
        }
    }

    /// Goes on from `at` while the pass walks, searches or runs a transit
    /// (not while its fill runs, nor once done): the robot was taken
    /// elsewhere and what the pass emitted was dropped.
    pub fn rejoin(&mut self, at: Cell) {
        if matches!(self.phase, Phase::Walk | Phase::Search | Phase::Transit) {
            self.jump_to(at);
        }
    }

    /// Marks the far goal visited (no longer way to it was found).
    pub fn give_up_far_goal<const GW: usize>(&mut self, fine: &mut Grid<GW>) {
        let (x, y) = self.far_goal.xy();
        done_with(fine, x, y);
        self.stats.unreachable += 1;
    }

    /// Abandons a search or transit under way (the caller used the shared
    /// search state or path buffer, or moved the robot); the pass resumes
    /// from the last cell it emitted.
    pub fn interrupt(&mut self) {
        if matches!(self.phase, Phase::Search | Phase::Transit) {
            self.phase = Phase::Walk;
            self.dir = (0, 0);
        }
    }

    /// True once every reachable boundary cell is visited.
    pub fn is_done(&self) -> bool {
        self.phase == Phase::Done
    }

    /// Starts a pass from `from` (a free cell) on a freshly built fine
    /// grid.
    pub fn start<const GW: usize>(&mut self, fine: &mut Grid<GW>, from: Cell) -> bool {
        fine.clear_layer(Layer::Covered);
        self.start_keeping(fine, from)
    }

    /// [`EdgePass::start`], but the boundary cells already marked covered
    /// count as visited: the stretches the lanes swept (the mission marks
    /// where the robot's centre went), or a pass begun before.
    pub fn start_keeping<const GW: usize>(&mut self, fine: &mut Grid<GW>, from: Cell) -> bool {
        let (x, y) = from.xy();
        if fine.is_blocked(x, y) {
            return false;
        }
        fine.clear_layer(Layer::Known);
        let _ = fine.set(Layer::Known, x, y, true);
        *self = Self::new();
        self.last = from;
        self.phase = Phase::Fill;
        true
    }

    /// One forward and one backward sweep of the reachability fill;
    /// true when something changed.
    fn sweep<const GW: usize>(fine: &mut Grid<GW>) -> bool {
        let (w, h) = (fine.width() as i32, fine.height() as i32);
        let mut changed = false;
        let mut visit = |fine: &mut Grid<GW>, x: i32, y: i32, back: i32| {
            if fine.is_free(x, y)
                && !fine.get(Layer::Known, x, y)
                && (fine.get(Layer::Known, x - back, y) || fine.get(Layer::Known, x, y - back))
            {
                let _ = fine.set(Layer::Known, x, y, true);
                changed = true;
            }
        };
        for y in 0..h {
            for x in 0..w {
                visit(fine, x, y, 1);
            }
        }
        for y in (0..h).rev() {
            for x in (0..w).rev() {
                visit(fine, x, y, -1);
            }
        }
        changed
    }

    /// The next thing to do. `path` is the transit buffer (as long as the
    /// longest transit, in fine cells); `search` the fine searches and
    /// `state` the search state they run on (lent; a transit search whose
    /// state was taken meanwhile is begun again).
    pub fn step<const N: usize, const NW: usize, const OPEN: usize, const GW: usize>(
        &mut self,
        fine: &mut Grid<GW>,
        search: &mut WindowSearch<N, NW>,
        state: &mut SearchState<N, NW, OPEN>,
        path: &mut [Cell],
        budget: u32,
    ) -> Result<EdgeStep, SearchError> {
        loop {
            match self.phase {
                Phase::Idle => return Err(SearchError::NotRunning),
                Phase::Done => return Ok(EdgeStep::Done),
                Phase::Fill => {
                    self.stats.sweeps += 1;
                    if Self::sweep(fine) {
                        return Ok(EdgeStep::Pending);
                    }
                    self.fill_done(fine);
                }
                Phase::Walk => return self.walk(fine, search, state),
                Phase::Search => match search.resume(state, budget) {
                    Ok(Progress::Pending { .. }) => return Ok(EdgeStep::Pending),
                    Ok(Progress::Found(_)) => {
                        self.path_len = search.write_path(state, path)?;
                        self.path_pos = 1;
                        self.phase = Phase::Transit;
                    }
                    Err(SearchError::NoPath) if self.boxed_in(search, state.nodes_expanded()) => {
                        // The map closed in on the robot since the fill
                        // (someone beside it mapped, a bump's mark): the
                        // goals are not unreachable, the robot is.
                        self.phase = Phase::Walk;
                        return Err(SearchError::StartBlocked);
                    }
                    Err(SearchError::NoPath) => {
                        // Unreachable: done with, not to be rechecked.
                        for &g in search.goals() {
                            done_with(fine, g.x as i32, g.y as i32);
                            self.stats.unreachable += 1;
                        }
                        self.phase = Phase::Walk;
                    }
                    Err(SearchError::Preempted) => self.phase = Phase::Walk,
                    Err(e) => return Err(e),
                },
                Phase::Transit => {
                    if let Some(step) = self.transit(fine, path) {
                        return Ok(step);
                    }
                }
            }
        }
    }

    /// The fill is complete. Unreachable free cells are of no use: block
    /// them so the boundary is the reachable one. Then walk.
    fn fill_done<const GW: usize>(&mut self, fine: &mut Grid<GW>) {
        let (w, h) = (fine.width() as i32, fine.height() as i32);
        let (mut free, mut reached) = (0u32, 0u32);
        for y in 0..h {
            for x in 0..w {
                if fine.is_free(x, y) {
                    free += 1;
                    if fine.get(Layer::Known, x, y) {
                        reached += 1;
                    } else {
                        let _ = fine.set_obstacle(x, y, true);
                    }
                }
            }
        }
        self.stats.free = free;
        self.stats.reached = reached;
        settle_driven(fine);
        self.visit_last(fine);
        self.phase = Phase::Walk;
    }

    /// [`boxed_in`] for a transit search that expanded `expanded` nodes:
    /// against the cells the fill reached, or the search window's when it
    /// holds fewer.
    fn boxed_in<const N: usize, const NW: usize>(
        &self,
        search: &WindowSearch<N, NW>,
        expanded: u32,
    ) -> bool {
        let win = search.window();
        let cells = u32::from(win.w) * u32::from(win.h);
        boxed_in(expanded, self.stats.reached.min(cells))
    }

    /// Marks the cell the pass stands on visited, if it was to do.
    fn visit_last<const GW: usize>(&mut self, fine: &mut Grid<GW>) {
        let (x, y) = self.last.xy();
        if todo(fine, x, y) {
            let _ = fine.set(Layer::Covered, x, y, true);
            self.stats.visited += 1;
        }
    }

    /// Along the contour; at its end, one grid scan for the nearest
    /// unvisited boundary cells and a search toward them.
    fn walk<const N: usize, const NW: usize, const OPEN: usize, const GW: usize>(
        &mut self,
        fine: &mut Grid<GW>,
        search: &mut WindowSearch<N, NW>,
        state: &mut SearchState<N, NW, OPEN>,
    ) -> Result<EdgeStep, SearchError> {
        if let Some(next) = self.next_on_contour(fine) {
            let (x, y) = next.xy();
            let _ = fine.set(Layer::Covered, x, y, true);
            self.stats.visited += 1;
            self.dir = (x - self.last.x as i32, y - self.last.y as i32);
            self.last = next;
            return Ok(EdgeStep::Move {
                to: next,
                edge: true,
            });
        }
        self.phase = Phase::Search;
        let mut goals = [Cell::new(0, 0); EDGE_GOALS];
        let n = self.nearest_todo(fine, &mut goals);
        if n == 0 {
            self.phase = Phase::Done;
            return Ok(EdgeStep::Done);
        }
        self.far_goal = goals.first().copied().unwrap_or(self.last);
        if let Err(e) = search.begin(
            state,
            fine,
            self.last,
            goals.get(..n).unwrap_or(&[]),
            Algo::AStar,
        ) {
            self.phase = Phase::Walk;
            return Err(e);
        }
        self.stats.transits += 1;
        Ok(EdgeStep::Pending)
    }

    /// The next cell of the transit path; `None` at its end (back to the
    /// walk).
    fn transit<const GW: usize>(&mut self, fine: &mut Grid<GW>, path: &[Cell]) -> Option<EdgeStep> {
        let Some(&next) = path
            .get(self.path_pos)
            .filter(|_| self.path_pos < self.path_len)
        else {
            self.visit_last(fine);
            self.dir = (0, 0);
            self.phase = Phase::Walk;
            return None;
        };
        self.path_pos += 1;
        self.last = next;
        Some(EdgeStep::Move {
            to: next,
            edge: false,
        })
    }

    /// The unvisited boundary neighbour closest to straight on (ties: the
    /// left turn, then orthogonal moves); diagonals never cut a corner.
    fn next_on_contour<const GW: usize>(&self, fine: &Grid<GW>) -> Option<Cell> {
        // E, NE, N, NW, W, SW, S, SE: each 45° to the left of the one before.
        const DIRS: [(i32, i32); 8] = crate::search::NEIGHBOURS;
        let (x, y) = self.last.xy();
        let cur = DIRS.iter().position(|&d| d == self.dir);
        let mut best: Option<(i32, Cell)> = None;
        for (k, &(dx, dy)) in DIRS.iter().enumerate() {
            let (nx, ny) = (x + dx, y + dy);
            if !todo(fine, nx, ny) {
                continue;
            }
            if dx != 0 && dy != 0 && (fine.is_blocked(x + dx, y) || fine.is_blocked(x, y + dy)) {
                continue;
            }
            let turn = match cur {
                // 0 straight, then left before right at each angle.
                Some(c) => {
                    let d = (k as i32 - c as i32).rem_euclid(8);
                    if d <= 4 {
                        2 * d
                    } else {
                        2 * (8 - d) + 1
                    }
                }
                None => i32::from(dx != 0 && dy != 0),
            };
            let Some(c) = Cell::from_xy(nx, ny) else {
                continue;
            };
            if best.is_none_or(|(b, _)| turn < b) {
                best = Some((turn, c));
            }
        }
        best.map(|(_, c)| c)
    }

    /// The unvisited boundary cells nearest to the last position.
    fn nearest_todo<const GW: usize>(&self, fine: &Grid<GW>, out: &mut [Cell]) -> usize {
        let (w, h) = (fine.width() as i32, fine.height() as i32);
        let (lx, ly) = (self.last.x as i64, self.last.y as i64);
        let cells = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| todo(fine, x, y))
            .filter_map(|(x, y)| Cell::from_xy(x, y));
        crate::math::select::smallest_k_of(cells, out, |c| {
            let (dx, dy) = (c.x as i64 - lx, c.y as i64 - ly);
            dx * dx + dy * dy
        })
    }
}
