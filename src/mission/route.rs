//! Long ways on the planning grid (issue 11 §3). The fine searches run in
//! a bounded window ([`crate::search::WindowSearch`]); when the two ends
//! of a detour, an edge-pass transit or the way home lie farther apart
//! than a window holds, or the window holds no way between them, the way
//! is first found on the whole fine map seen in blocks
//! ([`crate::search::WindowSearch::begin_blocks`]: 5 × 5 cells, 25 cm, for
//! the firmware's 12 m home in its 48 × 48 window). Not on the planning
//! cells: two of them on either side of a thin wall are neighbours there.
//! The blocks' centres are thinned greedily to the farthest one in plain
//! reach on the fine map, and fed one by one
//! through the executive's `enqueue`, which checks each leg again and
//! detours inside a window where something is in the way. At the host's
//! capacities every window is the whole map, so no route is ever taken.
//!
//! A block is open when any of its cells is free, so a wall thinner than
//! two blocks does not close the block search: each step of the path found
//! is checked on the fine map, and a block whose step crosses such a wall
//! is closed before searching again (up to [`LEAK_CLOSES`] times).
//!
//! Overflow policy: a route holds [`ROUTE`] waypoints; one that needs
//! more is not taken (the caller falls back as for a failed search). A
//! leg that finds no way drops the rest of its route; its owner (the
//! planner, the edge pass, the way home) plans again from where the robot
//! is.

use crate::nav::cspace;
use crate::nav::geometry::{nearest_free_fine, search_start_fine, segment_clear};
use crate::search::blocks::blocks_connected;
use crate::search::{Algo, Progress};
use crate::Cell;
use heapless::Vec;

/// Waypoints a route holds.
pub const ROUTE: usize = 64;

/// Blocks a route's search may close, one at a time, where its path
/// crossed a wall thinner than two blocks ([`crate::search::blocks`]);
/// past that the route is not taken.
pub const LEAK_CLOSES: usize = 4;

/// A route being fed: waypoints (world mm) and whether they clean.
#[derive(Clone, Debug, Default)]
pub struct Route {
    wps: Vec<(i32, i32), ROUTE>,
    pos: usize,
    cover: bool,
}

impl Route {
    /// An empty route.
    pub const fn new() -> Self {
        Self {
            wps: Vec::new(),
            pos: 0,
            cover: false,
        }
    }

    /// True while waypoints are left to feed.
    pub fn active(&self) -> bool {
        self.pos < self.wps.len()
    }

    /// `p` (world mm) is one of the route's waypoints.
    pub fn holds(&self, p: (i32, i32)) -> bool {
        self.wps.contains(&p)
    }

    /// Drops what is left.
    pub fn clear(&mut self) {
        self.wps.clear();
        self.pos = 0;
    }
}

sized_impl!([] {
    /// Plans a route from `from` to `to` (world mm) over the whole fine
    /// map in blocks and starts feeding it. False when there is none (the caller falls
    /// back as it would for a fine search that failed).
    pub(super) fn begin_route(&mut self, from: (i32, i32), to: (i32, i32), cover: bool) -> bool {
        let a = search_start_fine(self.p.map, self.p.fine, from, 3);
        let b = nearest_free_fine(self.p.map, self.p.fine, to);
        let (Some(a), Some(b)) = (a, b) else {
            return false;
        };
        let mut closed: Vec<Cell, LEAK_CLOSES> = Vec::new();
        let n = loop {
            let Some(n) = self.block_path(a, b, &closed) else {
                return false;
            };
            match self.leak(n) {
                None => break n,
                Some(c) => {
                    if closed.push(c).is_err() {
                        return false;
                    }
                }
            }
        };
        let Some(route) = self.thin_route(from, to, n, cover) else {
            return false;
        };
        self.m.route = route;
        self.m.counters.routes += 1;
        true
    }

    /// The block search from `a` to `b` (fine cells) with the `closed`
    /// blocks shut: its path (block centres) in `self.p.path`, and its
    /// length; None when there is none within one node budget.
    fn block_path(&mut self, a: Cell, b: Cell, closed: &[Cell]) -> Option<usize> {
        let budget = self.m.cfg.node_budget;
        let state = self.p.planner.search_state_mut();
        let search = &mut *self.p.search;
        search.begin_blocks(state, self.p.fine, (a, b), closed, Algo::AStar).ok()?;
        if !matches!(search.resume(state, budget), Ok(Progress::Found(_))) {
            return None;
        }
        search.write_path(state, self.p.path).ok()
    }

    /// The first step of the block path's `n` cells whose blocks do not
    /// meet on the fine map ([`blocks_connected`]: a thin wall between
    /// them), as the block to close before searching again: the one
    /// entered, or the one left when the one entered is the goal's; None
    /// when every step meets, or when the step that does not is the only
    /// one, from the start's block to the goal's: neither can be closed,
    /// and the route is taken as it was before the check (its legs are
    /// detoured inside their windows).
    fn leak(&self, n: usize) -> Option<Cell> {
        let side = self.p.search.block_side() as i32;
        let block = |i: usize| {
            self.p
                .path
                .get(i)
                .map(|c| (c.x as i32 / side, c.y as i32 / side))
        };
        for i in 1..n {
            let (Some(from), Some(to)) = (block(i - 1), block(i)) else {
                return None;
            };
            if blocks_connected(self.p.fine, from, to, side) {
                continue;
            }
            if i == 1 && i + 1 >= n {
                return None;
            }
            let shut = if i + 1 < n { to } else { from };
            return Cell::from_xy(shut.0, shut.1);
        }
        None
    }

    /// The route's waypoints: from `from`, greedily the farthest later
    /// point (the anchors of the `n` planning cells in `self.p.path`, then
    /// `to`) in plain reach on the fine map, as the queue checks it; a
    /// point with none in reach goes on to the next one, and its leg is
    /// detoured inside a window. `None` when they overflow [`ROUTE`].
    fn thin_route(&self, from: (i32, i32), to: (i32, i32), n: usize, cover: bool) -> Option<Route> {
        // A full margin (the queue checks half): a greedy leg otherwise
        // grazes the wall it turns around, closer than the guard allows.
        let r = (self.m.cfg.radius_mm + self.m.cfg.margin_mm) as i64;
        let point = |i: usize| match self.p.path.get(i).filter(|_| i < n) {
            Some(c) => cspace::fine_centre_mm(self.p.map, c.x as i32, c.y as i32),
            None => to,
        };
        let mut route = Route::new();
        route.cover = cover;
        let (mut at, mut k) = (from, 0usize);
        while k <= n {
            let next = (k + 1..=n)
                .rev()
                .find(|&i| segment_clear(self.p.map, at, point(i), r))
                .unwrap_or(k);
            at = point(next);
            route.wps.push(at).ok()?;
            k = next + 1;
        }
        Some(route)
    }

    /// Feeds the route's next legs while no fine path is being fed. True
    /// when nothing is left.
    pub(super) fn feed_route(&mut self) -> bool {
        while self.m.route.active() && self.m.feed.is_none() && self.m.queue.len() + 2 < super::QUEUE {
            let r = &mut self.m.route;
            let Some(&p) = r.wps.get(r.pos) else {
                break;
            };
            r.pos += 1;
            let cover = r.cover;
            self.m.in_route = true;
            self.enqueue(p, cover);
            self.m.in_route = false;
        }
        !self.m.route.active() && self.m.feed.is_none()
    }
});
