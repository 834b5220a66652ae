//! Cleaning lanes: the coverage planner on the planning cells
//! ([`crate::coverage`], [`crate::nav::cspace`]), each waypoint re-checked on
//! the fine map and detoured by A* on it when a wall's end is in the way,
//! and the fine path fed into the sub-path queue.

use super::{
    take_box, union_box, CellBox, Fault, Feed, Mission, Phase, BOXED_NODES, BOXED_PLAN_NODES,
    BOXED_TRIES, BOXED_WAIT_US, QUEUE,
};
use crate::coverage::{CoverageError, Step};
use crate::grid::Cell;
use crate::math::cost::dist_mm;
use crate::nav::cspace;
use crate::nav::geometry::{nearest_free_fine, prune_clear, search_start_fine, segment_clear};
use crate::robot::odometry::Pose;
use crate::search::{Algo, Progress, SearchError};
use crate::verify::metrics::SegmentKind;

/// A search that found the robot boxed in (see `Mission::boxed_in`):
/// what is searched for again, from where the robot then stands, once
/// `until_us` has passed.
///
/// `until_us` is `None` until the next cover step starts the wait's clock.
/// Starting it when the search fails, 0.1 s sooner (with the planner's
/// wait checked before the path being fed), was measured on 108
/// real-home missions: it shifts every later wait, and 8 missions came
/// out differently, two much worse (S6 unknown, seed 2: 97.4 to 87.0 %;
/// z10 unknown, seed 8: `NoWayHome`). The missions are that sensitive to
/// timing; the timing measured over all suites is kept.
#[derive(Clone, Copy, Debug)]
pub(super) struct BoxedWait {
    again: BoxedSearch,
    until_us: Option<u64>,
}

/// Cleaning detours that found no way, in a row, from one start: the
/// robot is boxed in even when its pocket holds more than
/// [`BOXED_NODES`] fine cells. A person who stood by the robot against a
/// wall left it a pocket of 202-389 cells (the z10 home, unknown mode,
/// realistic noise, 1 person, seed 6): every goal the planner offered
/// failed from there, 159 in 21 s, the rest of the home taken as covered
/// and a room left unswept (93.06 %). Goals that all fail from where the
/// robot stands say the start is shut in, not each goal out of reach: from
/// the second such failure in a row within [`POCKET_MM`] of the first, in
/// a pocket under [`POCKET_NODES`], the lanes wait as when boxed in. Once
/// the waits are spent there (`spent`), goals are skipped as before, so a
/// pocket that stays shut costs 30 s once, not 30 s a goal.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pocket {
    from: (i32, i32),
    fails: u8,
    spent: bool,
}

/// Boxed-in waits in a row after which unknown mode forgets the bumper's
/// marks (5 s, as the edge pass does when boxed in): the person who shut
/// the robot in walked into it, and the marks of those bumps kept the
/// pocket shut after they left (the [`Pocket`] case: 30 s waited, then
/// every goal skipped all the same).
const FORGET_MARKS_BOXED: u8 = 5;

/// Starts of failed detours within this of each other are one pocket, mm
/// (the robot stands still while the goals fail).
pub const POCKET_MM: i64 = 100;

/// A failed detour that expanded this many fine cells or more (2 m² for
/// the robot's centre, four times [`BOXED_NODES`]) searched a region, not
/// a pocket ([`Pocket`]).
pub const POCKET_NODES: u32 = 4 * BOXED_NODES;

impl Pocket {
    /// No detour failed yet.
    pub(super) const fn new() -> Self {
        Self {
            from: (0, 0),
            fails: 0,
            spent: false,
        }
    }

    /// Counts a detour from `from` that found no way having expanded
    /// `expanded` fine cells; true when it is the second or later in a row
    /// from the same pocket and the pocket's waits are not spent.
    fn failed(&mut self, from: (i32, i32), expanded: u32) -> bool {
        if expanded >= POCKET_NODES {
            *self = Self::new();
            return false;
        }
        if self.fails == 0 || dist_mm(self.from, from) > POCKET_MM {
            *self = Self {
                from,
                fails: 0,
                spent: false,
            };
        }
        self.fails = self.fails.saturating_add(1);
        self.fails >= 2 && !self.spent
    }
}

/// The search a boxed-in wait repeats.
#[derive(Clone, Copy, Debug)]
pub(super) enum BoxedSearch {
    /// A cleaning detour to this point (fine cells).
    Detour((i32, i32)),
    /// The coverage planner's search for its next goal (planning cells):
    /// the goals it gave up meanwhile are taken up again.
    Planner,
}

/// Every planning cell (clipped to the grid when derived).
pub(super) const ALL_CELLS: CellBox = (0, 0, i32::MAX / 4, i32::MAX / 4);

impl Mission {
    /// The map's states changed in `fine` (evidence cells of `res_mm`):
    /// the planning cells around them are derived again at the next
    /// refresh, and the fine configuration space is rebuilt before the
    /// next detour.
    pub(super) fn note_map_change(&mut self, res_mm: u32, fine: CellBox) {
        let r = (self.cfg.radius_mm + self.cfg.margin_mm) as u32;
        let b = cspace::coarse_box_of(res_mm, self.cfg.plan_cell_mm, r, fine);
        self.coarse_dirty = union_box(self.coarse_dirty, b);
        self.fine_stale = true;
    }

    /// A planning cell set by hand: derived from the map again at the
    /// next refresh (as every cell was when each refresh derived all).
    pub(super) fn note_coarse_set(&mut self, gx: i32, gy: i32) {
        self.coarse_dirty = union_box(self.coarse_dirty, (gx, gy, gx, gy));
    }
}

sized_impl!([] {
    /// The cover phase's step: map upkeep, avoidance, the fine path being
    /// fed, the planner's next waypoints; the edge pass when it is done.
    pub(super) fn cover_step(&mut self, now_us: u64, pose: &Pose) {
        if self.scroll_when_due(now_us, pose) {
            return;
        }
        self.trace_lanes(pose);
        self.refresh_coarse();
        self.watch_corridor(now_us, pose);
        // A detour's wait holds the feeding; the planner's, only the
        // planner (the path being fed, if any, is driven first).
        if self.boxed_waiting(now_us, pose, false)
            || !self.feed_path()
            || !self.feed_route()
            || self.boxed_waiting(now_us, pose, true)
        {
            return;
        }
        self.top_up_cover();
        let m = &mut *self.m;
        if !(m.planner_done && m.queue.is_empty() && m.feed.is_none()) {
            return;
        }
        // Without a room tour, the edge pass runs once over the home;
        // with one, over each room once its lanes are done.
        if !m.rooms.on() || m.rooms.edge_due {
            self.start_edge(pose);
        } else if !self.next_room() {
            self.m.phase = Phase::ReturnSearch;
            self.begin_return(pose);
        }
    }

    /// After a map update (unknown mode, or known mode with updates): the
    /// planning cells follow the map (the planner's own cell stays free so
    /// it can always search from it). Only the cells the update can have
    /// changed are derived again ([`Mission::note_map_change`]), with
    /// those set by hand since the last refresh: the same grid as deriving
    /// all, at a fraction of the work (deriving all 41 × 41 cells took up
    /// to 22 M instructions, after every revolution).
    pub(super) fn refresh_coarse(&mut self) {
        let m = &mut *self.m;
        if !m.map_dirty {
            return;
        }
        m.map_dirty = false;
        let Some(dirty) = take_box(&mut m.coarse_dirty) else {
            return;
        };
        let r = (m.cfg.radius_mm + m.cfg.margin_mm) as u32;
        let cell = m.cfg.plan_cell_mm;
        if cspace::update_coarse_in(self.p.map, self.p.coarse, cell, r, false, dirty).is_err() {
            self.fail(Fault::Capacity);
            return;
        }
        self.fence(dirty);
        let (x, y) = self.p.planner.position().xy();
        let _ = self.p.coarse.set_obstacle(x, y, false);
        self.m.note_coarse_set(x, y);
    }

    pub(super) fn start_cover(&mut self, now_us: u64, pose: &Pose) {
        self.begin_trace();
        self.m.map_dirty = true;
        self.m.coarse_dirty = ALL_CELLS;
        self.refresh_coarse();
        let m = &mut *self.m;
        let cell = m.cfg.plan_cell_mm;
        let (cx, cy) = cspace::coarse_of(self.p.map, cell, pose.x_mm, pose.y_mm);
        // The planning cell the robot is in, or the nearest free one.
        let mut best: Option<(i64, Cell)> = None;
        for dy in -2..=2 {
            for dx in -2..=2 {
                let (x, y) = (cx + dx, cy + dy);
                if !self.p.coarse.is_free(x, y) {
                    continue;
                }
                let d = dist_mm(self.anchor(x, y), (pose.x_mm, pose.y_mm));
                if best.is_none_or(|(b, _)| d < b) {
                    best = Cell::from_xy(x, y).map(|c| (d, c));
                }
            }
        }
        let Some((_, start)) = best else {
            self.fail(Fault::StartBlocked);
            return;
        };
        let started = if self.m.restored {
            self.p.planner.start_keeping(self.p.coarse, start)
        } else {
            self.p.planner.start(self.p.coarse, start)
        };
        if started.is_err() {
            self.fail(Fault::StartBlocked);
            return;
        }
        self.enter_first_room(start);
        let m = &mut *self.m;
        m.queue.reset((pose.x_mm, pose.y_mm));
        m.phase = Phase::Cover;
        m.subpath_since_us = now_us;
        let to = self.anchor(start.x as i32, start.y as i32);
        self.enqueue(to, true);
    }

    /// World mm where the robot stands for planning cell (x, y).
    pub(super) fn anchor(&self, x: i32, y: i32) -> (i32, i32) {
        let c = &self.m.cfg;
        let r = (c.radius_mm + c.margin_mm) as u32;
        cspace::anchor_mm(self.p.map, c.plan_cell_mm, r, x, y)
    }

    /// Asks the planner for waypoints until a few are queued.
    pub(super) fn top_up_cover(&mut self) {
        let budget = self.m.cfg.node_budget;
        while self.m.queue.len() < 4
            && !self.m.planner_done
            && self.m.feed.is_none()
            && self.m.boxed_wait.is_none()
            && !self.m.route.active()
        {
            match self.p.planner.step(self.p.coarse, budget) {
                Ok(Step::Move(w)) => {
                    let (x, y) = w.to.xy();
                    let to = self.anchor(x, y);
                    self.enqueue(to, w.kind == SegmentKind::Cover);
                }
                Ok(Step::Pending) => break,
                Ok(Step::Done) => {
                    if self.boxed_in_planner() {
                        break;
                    }
                    // Goals given up while the map was different (a person
                    // in a doorway) get up to two more chances.
                    let at = self.p.planner.position();
                    if self.m.abandon_rounds < 2
                        && (self.p.planner.retry_abandoned(at) + self.hand_back_skipped(at)) > 0
                    {
                        self.m.abandon_rounds += 1;
                        self.m.counters.abandoned_retries += 1;
                    } else {
                        self.m.planner_done = true;
                    }
                }
                Err(CoverageError::Search(SearchError::StartBlocked)) => {
                    // The map moved under the planner: free its cell and
                    // try again next step.
                    let (x, y) = self.p.planner.position().xy();
                    let _ = self.p.coarse.set_obstacle(x, y, false);
                    self.m.note_coarse_set(x, y);
                    break;
                }
                Err(_) => {
                    self.fail(Fault::Capacity);
                    break;
                }
            }
        }
    }

    /// A cleaning detour's search found no way having expanded under
    /// [`BOXED_NODES`]: the robot is boxed in (a person beside it), not the
    /// goal out of reach. Instead of skipping the goal (and, the planner
    /// offering the next one each step, every goal while the person
    /// stays), the lanes wait and the same goal is searched again
    /// ([`Self::boxed_in`]); then it is skipped as before. True when the
    /// mission waits.
    fn boxed_in_detour(&mut self, f: &Feed, expanded: u32) -> bool {
        if self.m.phase != Phase::Cover || !f.cover {
            return false;
        }
        let pocket = self.m.pocket.failed(f.from, expanded);
        if expanded >= BOXED_NODES && !pocket {
            return false;
        }
        let waits = self.boxed_in(BoxedSearch::Detour(f.then.unwrap_or(f.from)));
        if !waits && pocket {
            self.m.pocket.spent = true;
        }
        waits
    }

    /// The coverage planner finished because its last search gave goals
    /// up having expanded under [`BOXED_PLAN_NODES`] planning cells: the
    /// robot is boxed in, and the goals are taken up again after a wait
    /// ([`Self::boxed_in`]) rather than by spending the planner's rounds of
    /// second chances at once. True when the mission waits.
    fn boxed_in_planner(&mut self) -> bool {
        let expanded = self.p.planner.search_state_mut().nodes_expanded();
        let abandoned = self.p.planner.stats().abandoned_goals;
        let fresh = abandoned > self.m.plan_abandoned_seen;
        self.m.plan_abandoned_seen = abandoned;
        fresh && expanded < BOXED_PLAN_NODES && self.boxed_in(BoxedSearch::Planner)
    }

    /// The robot is boxed in: wait [`BOXED_WAIT_US`], then run `again`
    /// from where the robot then stands, up to [`BOXED_TRIES`] times
    /// before a detour finds its way. False (and the count starts again)
    /// once they are spent. The wait's clock starts at the next cover
    /// step ([`BoxedWait`]).
    fn boxed_in(&mut self, again: BoxedSearch) -> bool {
        let m = &mut *self.m;
        if m.boxed_tries >= BOXED_TRIES {
            m.boxed_tries = 0;
            return false;
        }
        m.boxed_tries += 1;
        m.boxed_wait = Some(BoxedWait {
            again,
            until_us: None,
        });
        if m.boxed_tries == FORGET_MARKS_BOXED {
            self.forget_marks();
        }
        true
    }

    /// The lanes wait out a boxed-in search ([`Self::boxed_in`]) of the
    /// planner (`planner`) or of a detour; when the wait is over, the
    /// detour is searched for again from the queue's end (or the robot),
    /// or the planner takes its given-up goals up again from its cell.
    /// True while waiting.
    fn boxed_waiting(&mut self, now_us: u64, pose: &Pose, planner: bool) -> bool {
        let m = &mut *self.m;
        let Some(mut w) = m.boxed_wait else {
            return false;
        };
        if matches!(w.again, BoxedSearch::Planner) != planner {
            return false;
        }
        let until_us = *w.until_us.get_or_insert(now_us + BOXED_WAIT_US);
        if now_us < until_us {
            m.boxed_wait = Some(w);
            return true;
        }
        m.boxed_wait = None;
        match w.again {
            BoxedSearch::Detour(to) => {
                let from = m.queue.last_end().unwrap_or((pose.x_mm, pose.y_mm));
                self.detour(from, to, true);
                true
            }
            BoxedSearch::Planner => {
                let at = self.p.planner.position();
                self.p.planner.retry_abandoned(at);
                false
            }
        }
    }

    /// Queues a straight move to `to`, or a detour on the fine map when the
    /// straight segment is not clear.
    pub(super) fn enqueue(&mut self, to: (i32, i32), cover: bool) {
        let m = &mut *self.m;
        let from = m.queue.last_end().unwrap_or(to);
        let r = m.cfg.sweep_mm();
        if segment_clear(self.p.map, from, to, r) {
            if !m.queue.push(to, cover) {
                self.fail(Fault::Capacity);
            }
            return;
        }
        self.detour(from, to, cover);
    }

    /// Queues an A* path on the fine configuration space from `from` to
    /// `to` (the fine grid is rebuilt first when the map changed during
    /// coverage; the edge pass's grid is used as it is).
    pub(super) fn detour(&mut self, from: (i32, i32), to: (i32, i32), cover: bool) {
        if self.m.fine_stale && !self.m.fine_is_edge && !self.rebuild_fine() {
            return;
        }
        self.m.edge.interrupt();
        let a = self.start_fine(from);
        let b = nearest_free_fine(self.p.map, self.p.fine, to);
        let m = &mut *self.m;
        let (Some(a), Some(b)) = (a, b) else {
            // Not representable on the fine map: drive straight (the guard
            // still protects).
            let _ = m.queue.push(to, cover);
            return;
        };
        m.counters.detours += 1;
        let state = self.p.planner.search_state_mut();
        match self.p.search.begin(state, self.p.fine, a, &[b], Algo::AStar) {
            Ok(()) => {}
            Err(SearchError::OutOfWindow) if self.begin_route(from, to, cover) => return,
            Err(_) => {
                let _ = self.m.queue.push(to, cover);
                return;
            }
        }
        let m = &mut *self.m;
        m.feed = Some(Feed {
            searching: true,
            len: 0,
            pos: 0,
            cover,
            then: Some(to),
            from,
            routable: !m.in_route,
        });
    }

    /// The fine configuration space built again from the map (the
    /// lanes' grid, not the edge pass's). False, with the mission failed,
    /// when it does not fit.
    fn rebuild_fine(&mut self) -> bool {
        let r = (self.m.cfg.radius_mm + self.m.cfg.margin_mm) as u32;
        if cspace::build_fine(self.p.map, self.p.fine, r, false).is_err() {
            self.fail(Fault::Capacity);
            return false;
        }
        self.m.fine_stale = false;
        true
    }

    /// Where a detour from `from` starts ([`search_start_fine`]). When
    /// there is none and bumper marks lie by the robot, they may be what
    /// shuts it in: they are forgotten there (unknown mode,
    /// [`Self::forget_marks_near`]) and the start looked for again. A glass
    /// pane standing free in a room (the 1c home, unknown mode, harsh
    /// noise, seed 8) was bumped along; its marks spread past the pane's
    /// end and shut the robot in beside it. With no start, a detour drives
    /// straight to its goal under the guard, which cannot see glass: 855
    /// bumps, and the battery ran flat 4.4 m from the dock. What the
    /// bumper meets again is marked again.
    fn start_fine(&mut self, from: (i32, i32)) -> Option<Cell> {
        let a = search_start_fine(self.p.map, self.p.fine, from, 3);
        if a.is_some() || self.m.fine_is_edge || !self.forget_marks_near(from) {
            return a;
        }
        if !self.rebuild_fine() {
            return None;
        }
        search_start_fine(self.p.map, self.p.fine, from, 3)
    }

    /// Advances the fine path being fed (search, then queueing its cells).
    /// True when nothing is left to feed.
    pub(super) fn feed_path(&mut self) -> bool {
        let Some(mut f) = self.m.feed else {
            return true;
        };
        if f.searching {
            let state = self.p.planner.search_state_mut();
            let search = &mut *self.p.search;
            let progress = search.resume(state, self.m.cfg.node_budget);
            let expanded = state.nodes_expanded();
            if progress == Err(SearchError::NoPath) && self.boxed_in_detour(&f, expanded) {
                self.m.feed = None;
                return true;
            }
            match progress {
                Ok(Progress::Pending { .. }) => return false,
                Ok(Progress::Found(_)) => match self
                    .p
                    .search
                    .write_path(self.p.planner.search_state_mut(), self.p.path)
                {
                    Ok(n) => {
                        self.m.boxed_tries = 0;
                        self.m.pocket = Pocket::new();
                        let r = self.m.cfg.sweep_mm();
                        f.len =
                            prune_clear(self.p.map, self.p.path.get_mut(..n).unwrap_or(&mut []), r);
                        f.searching = false;
                    }
                    Err(_) => {
                        self.fail(Fault::Capacity);
                        return false;
                    }
                },
                Err(SearchError::Preempted) => {
                    // The shared state went to another query (nothing does
                    // this today: the planner waits while a path is fed):
                    // search again.
                    self.m.feed = None;
                    self.detour(f.from, f.then.unwrap_or(f.from), f.cover);
                    return false;
                }
                Err(SearchError::NoPath) if f.routable && !self.p.search.is_whole() => {
                    // No way inside the window: a longer way round, on the
                    // planning cells.
                    self.m.feed = None;
                    let to = f.then.unwrap_or(f.from);
                    if self.begin_route(f.from, to, f.cover) {
                        if self.m.phase == Phase::ReturnSearch {
                            self.m.phase = Phase::Return;
                        }
                        return false;
                    }
                    self.skip_goal(&f);
                    return true;
                }
                Err(SearchError::NoPath) => {
                    self.m.feed = None;
                    if !f.routable {
                        // A route's leg found no way: the route is broken;
                        // its owner plans again from where the robot is.
                        self.m.route.clear();
                    }
                    if self.m.phase == Phase::ReturnSearch {
                        // No way home on this map: plan again from a fresh
                        // map (the Return phase counts the tries).
                        self.m.phase = Phase::Return;
                        self.m.fine_is_edge = false;
                    } else {
                        self.skip_goal(&f);
                    }
                    return true;
                }
                Err(_) => {
                    self.fail(Fault::Capacity);
                    return false;
                }
            }
        }
        let m = &mut *self.m;
        while f.pos < f.len && m.queue.len() + 1 < QUEUE {
            let Some(&c) = self.p.path.get(f.pos) else {
                break;
            };
            let p = cspace::fine_centre_mm(self.p.map, c.x as i32, c.y as i32);
            if !m.queue.push(p, f.cover) {
                break;
            }
            f.pos += 1;
        }
        if f.pos < f.len {
            m.feed = Some(f);
            return false;
        }
        if let Some(t) = f.then {
            if m.queue.len() + 1 >= QUEUE || !m.queue.push(t, f.cover) {
                m.feed = Some(f);
                return false;
            }
        }
        m.feed = None;
        true
    }
});

#[cfg(test)]
mod tests {
    use super::*;

    /// Detours failing in a row from one start make a pocket from the
    /// second on; a start elsewhere or a search of a region starts again;
    /// spent waits are not taken again until the pocket changes.
    #[test]
    fn goals_failing_from_one_start_are_a_pocket() {
        let mut p = Pocket::new();
        let at = (7270, 2530);
        assert!(!p.failed(at, 389), "one failure is the goal's");
        assert!(p.failed((at.0 + 60, at.1 - 40), 380), "the same pocket");
        assert!(p.failed(at, 202), "it may shrink (a bump's marks)");
        p.spent = true;
        assert!(!p.failed(at, 202), "its waits were spent");
        assert!(!p.failed((at.0 + 500, at.1), 300), "elsewhere: first again");
        assert!(p.failed((at.0 + 500, at.1), 300));
        assert!(!p.failed((at.0 + 500, at.1), POCKET_NODES), "a region");
        assert!(!p.failed((at.0 + 500, at.1), 300), "first after a region");
    }
}
