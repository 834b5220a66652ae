//! The shared best-first search machinery behind A*, OHA* and Theta*.
//!
//! One loop serves every algorithm; they differ only in the heuristic
//! ([`super::heuristics`]) and, for Theta*, in the parent update
//! ([`super::theta`]). Breadth-first and depth-first search (seed 004's
//! baselines) run in it too: their key is the push count, rising for BFS
//! (first in, first out) and falling for DFS (last in, first out), and a
//! cell keeps the parent that discovered it. The search is 8-connected with octile step costs
//! and **no corner cutting**: a diagonal step needs both orthogonal
//! neighbours free. It is multi-goal: it stops at the first goal it closes,
//! with the heuristic taken as the minimum over the goals (ALGORITHMS.md §1,
//! eq. 4).
//!
//! The search is **resumable**: [`SearchState::begin`] sets up a query and
//! [`SearchState::resume`] expands at most a given number of nodes per call,
//! so the firmware can bound the time of each control-loop tick.
//! [`SearchState::search`] runs a query to completion.

use super::heuristics;
use super::open_list::{Entry, Order};
use super::state::{
    check_goal, check_start, Algo, Node, Progress, SearchError, SearchState, SearchStats, FOUND,
    IDLE, MAX_GOALS, NEIGHBOURS, RUNNING,
};
use super::theta;
use crate::grid::{Cell, Grid};
use crate::math::cost::{COST_DIAGONAL, COST_PER_CELL};
use crate::math::divide::RowDivider;

impl<const N: usize, const NW: usize, const OPEN: usize> SearchState<N, NW, OPEN> {
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
        self.query = self.query.wrapping_add(1);
        let cells = grid.cells();
        if cells > N || cells > NW * 32 {
            return Err(SearchError::MapTooLarge);
        }
        let si = check_start(grid, start)?;
        if goals.is_empty() {
            return Err(SearchError::NoGoals);
        }
        if goals.len() > MAX_GOALS {
            return Err(SearchError::TooManyGoals);
        }
        for (slot, &goal) in self.goals.iter_mut().zip(goals) {
            check_goal(grid, goal)?;
            *slot = goal;
        }
        self.goal_count = goals.len() as u32;
        let (gx, gy) = self.goals[0].xy();
        self.goal_index = grid.index(gx, gy).map_or(u32::MAX, |g| g as u32);
        self.start = start;
        self.algo = algo;
        self.width = grid.width();
        self.height = grid.height();
        self.rows = RowDivider::new(grid.width() as u16);
        self.steps = index_steps(grid.width() as i32);
        self.nodes = 0;
        self.pushes = 0;
        self.seen.clear_prefix(cells);
        self.closed.clear_prefix(cells);
        self.open.clear_for(open_order(algo));
        self.set_node(si, 0, si as u32);
        let f = self.key(start, 0);
        self.open
            .push(Entry {
                f,
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
        if self.algo == Algo::AStarOctile {
            self.drive::<OCTILE, GW>(grid, budget)
        } else if self.algo != Algo::Jps {
            self.drive::<GENERIC, GW>(grid, budget)
        } else {
            self.drive_jumps(grid, budget)
        }
    }

    /// [`Self::drive`] for jump point search, out of line so that the
    /// other two loops compile as they did without it.
    #[inline(never)]
    fn drive_jumps<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        budget: u32,
    ) -> Result<Progress, SearchError> {
        self.drive::<JUMPS, GW>(grid, budget)
    }

    /// The loop of [`SearchState::resume`], compiled three times (issue
    /// 13, search speed): [`OCTILE`] for A* octile, whose key, open list
    /// and neighbour test are then fixed at compile time (no per-neighbour
    /// dispatch on the algorithm), [`JUMPS`] for jump point search
    /// ([`super::jps`]), and [`GENERIC`] for every other algorithm.
    #[inline(always)]
    fn drive<const MODE: u8, const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        budget: u32,
    ) -> Result<Progress, SearchError> {
        let mut left = budget;
        while left > 0 {
            let popped = if MODE == OCTILE {
                self.open.dial_pop()
            } else {
                self.open.pop()
            };
            let Some(e) = popped else {
                self.phase = IDLE;
                return Err(SearchError::NoPath);
            };
            let i = e.idx as usize;
            if self.closed.test_and_set(i) {
                continue; // stale duplicate (lazy deletion)
            }
            self.nodes = self.nodes.saturating_add(1);
            left -= 1;
            let cell = self.cell_of(i);
            if self.is_goal(e.idx, cell) {
                self.phase = FOUND;
                self.found = e.idx;
                return Ok(Progress::Found(self.stats(e.idx)));
            }
            let expanded = if MODE == OCTILE {
                let (x, y) = cell.xy();
                self.expand_octile(i, (x, y), self.open_moves(grid, i, (x, y)))
            } else if MODE == JUMPS {
                self.expand_jps(grid, i, cell.xy())
            } else {
                self.expand(grid, i, cell)
            };
            if let Err(err) = expanded {
                self.phase = IDLE;
                return Err(err);
            }
        }
        Ok(Progress::Pending {
            nodes_expanded: self.nodes,
        })
    }

    /// Whether the cell at index `idx` (= `cell`) is a goal: one compare
    /// for a single goal (the index kept by `begin`), a scan otherwise.
    #[inline(always)]
    fn is_goal(&self, idx: u32, cell: Cell) -> bool {
        idx == self.goal_index || (self.goal_count > 1 && self.goals().contains(&cell))
    }

    /// [`Self::expand`] for A* octile, over the `moves` out of cell `i` =
    /// (x, y) into cells not closed ([`Self::open_moves`]). The key is the octile distance
    /// ([`heuristics::octile_nearest`]) and the open list the dial
    /// ([`super::open_list::dial`]).
    #[inline(always)]
    fn expand_octile(
        &mut self,
        i: usize,
        (x, y): (i32, i32),
        mut moves: u32,
    ) -> Result<(), SearchError> {
        let gs = self.g_at(i);
        while let Some(k) = take_move(&mut moves) {
            let ni = (i as i32).wrapping_add(pick(&self.steps, k)) as usize;
            let cand = gs.saturating_add(pick(&STEP_COST, k));
            let Some(node) = self.node.get_mut(ni) else {
                continue;
            };
            if self.seen.get(ni) && cand >= node.g {
                continue;
            }
            *node = Node {
                g: cand,
                parent: i as u32,
            };
            self.seen.put(ni, true);
            let (dx, dy) = pick(&NEIGHBOURS, k);
            let h = self.octile_h(x + dx, y + dy);
            self.open
                .dial_push(cand.saturating_add(h), ni as u32)
                .map_err(|_| SearchError::OpenListFull)?;
        }
        Ok(())
    }

    /// The moves out of cell `i` = (x, y) into cells not closed: the
    /// grid's moves ([`Grid::moves`]) less the closed ring around `i`, read
    /// as the grid reads its obstacles, so closed neighbours are dropped
    /// eight at a time instead of tested one by one.
    #[inline(always)]
    fn open_moves<const GW: usize>(&self, grid: &Grid<GW>, i: usize, (x, y): (i32, i32)) -> u32 {
        grid.moves_at(i, x, y) & !self.closed.ring(i, self.width as usize, x == 0)
    }

    /// The octile distance from (x, y) to the nearest goal: with one goal,
    /// straight to it, in plain 32-bit arithmetic (cells are `u16`, so
    /// 65,535 × 8,119 < 2^30 cannot overflow: no saturating steps).
    #[inline(always)]
    pub(super) fn octile_h(&self, x: i32, y: i32) -> u32 {
        if self.goal_count == 1 {
            let g = self.goals[0];
            let dx = (g.x as i32 - x).unsigned_abs() & 0xFFFF;
            let dy = (g.y as i32 - y).unsigned_abs() & 0xFFFF;
            let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
            lo * COST_DIAGONAL + (hi - lo) * COST_PER_CELL
        } else {
            heuristics::octile_nearest(Cell::new(x as u16, y as u16), self.goals())
        }
    }

    /// Relaxes the neighbours of cell `i` = `cell`. A tight loop (issue
    /// 13, search speed): the moves out of the cell come as one mask
    /// ([`Grid::moves`]: three rows of three bits, the no-corner-cutting
    /// rule by shifts), and only the cells left are visited.
    fn expand<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        i: usize,
        cell: Cell,
    ) -> Result<(), SearchError> {
        let (x, y) = cell.xy();
        let gs = self.g_at(i);
        let mut moves = self.open_moves(grid, i, (x, y));
        let theta = self.algo == Algo::Theta;
        let blind = matches!(self.algo, Algo::Bfs | Algo::Dfs);
        while let Some(k) = take_move(&mut moves) {
            let (dx, dy) = pick(&NEIGHBOURS, k);
            // Inside the map (the mask says so): the index is i + dy·w + dx.
            let ni = (i as i32).wrapping_add(pick(&self.steps, k)) as usize;
            let step = pick(&STEP_COST, k);
            let (nx, ny) = (x + dx, y + dy);
            let (cand, par) = if theta {
                theta::relax(self, grid, i, gs, (nx, ny), step)
            } else {
                (gs.saturating_add(step), i as u32)
            };
            let better = !self.seen.get(ni) || (!blind && cand < self.g_at(ni));
            if better {
                self.set_node(ni, cand, par);
                let f = self.key(Cell::new(nx as u16, ny as u16), cand);
                self.open
                    .push(Entry {
                        f,
                        g: cand,
                        idx: ni as u32,
                    })
                    .map_err(|_| SearchError::OpenListFull)?;
            }
        }
        Ok(())
    }

    /// The open list's key of cell `s` reached at cost `g`: g + h for the
    /// best-first searches, the push count for BFS and DFS.
    #[inline(always)]
    fn key(&mut self, s: Cell, g: u32) -> u32 {
        let n = self.pushes;
        self.pushes = n.saturating_add(1);
        let h = match self.algo {
            Algo::AStar | Algo::Theta => heuristics::euclidean(s, self.goals()),
            Algo::Oha => heuristics::oha(s, self.start, self.goals()),
            Algo::AStarOctile | Algo::Jps => heuristics::octile_nearest(s, self.goals()),
            Algo::Bfs => return n,
            Algo::Dfs => return u32::MAX - n,
        };
        g.saturating_add(h)
    }
}

/// [`SearchState::drive`]'s modes: A* octile's loop, jump point search's,
/// and every other algorithm's.
const OCTILE: u8 = 0;
const JUMPS: u8 = 1;
const GENERIC: u8 = 2;

/// The step cost of each move, in the order of [`NEIGHBOURS`] (the odd
/// ones diagonal).
const STEP_COST: [u32; 8] = [
    COST_PER_CELL,
    COST_DIAGONAL,
    COST_PER_CELL,
    COST_DIAGONAL,
    COST_PER_CELL,
    COST_DIAGONAL,
    COST_PER_CELL,
    COST_DIAGONAL,
];

/// Takes the lowest move out of a move mask ([`Grid::moves`]): its
/// neighbour number, in the order of [`NEIGHBOURS`].
#[inline(always)]
fn take_move(moves: &mut u32) -> Option<usize> {
    if *moves == 0 {
        return None;
    }
    let k = (moves.trailing_zeros() & 7) as usize;
    *moves &= *moves - 1;
    Some(k)
}

/// Entry `k` of an eight-entry table: `k < 8` (a bit of a move mask), so
/// the compiler drops the check and the fallback is never taken.
#[inline(always)]
fn pick<T: Copy + Default>(table: &[T; 8], k: usize) -> T {
    table.get(k).copied().unwrap_or_default()
}

/// The linear index step to each neighbour on a map `w` cells wide, in
/// the order of [`NEIGHBOURS`].
const fn index_steps(w: i32) -> [i32; 8] {
    [1, 1 - w, -w, -1 - w, -1, w - 1, w, w + 1]
}

/// The open list's order for `algo`: the dial for A* octile, whose
/// heuristic is consistent (its keys never fall: [`Order::Monotone`]); the
/// heap's strict order for the rest, whose results (the Euclidean A* of
/// Table 1 and the mission, OHA*, Theta*, BFS, DFS) it keeps exactly.
fn open_order(algo: Algo) -> Order {
    match algo {
        Algo::AStarOctile => Order::Monotone,
        _ => Order::Strict,
    }
}
