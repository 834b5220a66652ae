//! Recovering: failing with a typed fault, replaying control's give-ups,
//! putting the cells of a sub-path the robot could not drive back for a
//! later pass, and planning a leg again when the guard held the robot.

use super::handoff::Note;
use super::{Activity, Fault, Feed, MapMode, Phase, MAX_RETRIES, QUEUE};
use crate::grid::{Cell, Layer};
use crate::math::cost::dist_mm;
use crate::nav::cspace;
use crate::nav::follow::SubPath;
use crate::robot::odometry::Pose;

/// The point `k / steps` of the way from `a` to `b`, mm.
fn lerp_mm(a: (i32, i32), b: (i32, i32), k: i64, steps: i64) -> (i32, i32) {
    let at = |p: i32, q: i32| (p as i64 + (q - p) as i64 * k / steps.max(1)) as i32;
    (at(a.0, b.0), at(a.1, b.1))
}

/// How often the edge pass takes back the contour where it gave a
/// sub-path up, per place (within [`super::bump::SAME_PLACE_MM`], over the
/// last two places). A wall face the lidar grazes
/// flickers between occupied and free: the pass's grid, built while a
/// stretch of it read free, put contour cells 50 mm into the face, the leg
/// to each was judged blocked on the live map and given up, and each give-
/// up reopened the stretch. The pass went to and fro under a kitchen
/// island for 100 s, 35 times, until its retry budget ran out (the studio
/// rerun after a power loss, realistic, seed 1). Twice is enough for a
/// person who stood on the contour to step off. Two places: a to and fro
/// has two ends.
pub(super) const EDGE_REOPENS_PER_PLACE: u8 = 2;

sized_impl!([] {
    pub(super) fn fail(&mut self, f: Fault) {
        self.m.phase = Phase::Failed(f);
        self.m.activity = Activity::Follow;
    }

    /// Replays what control handed off since the last step, in order.
    pub(super) fn drain(&mut self) {
        // By reference: a heapless::Vec's by-value iterator slices its
        // storage on drop (a panicking branch in the firmware).
        for &note in self.m.handoff.take().iter() {
            match note {
                Note::Swept((gx, gy)) => {
                    let _ = self.p.coarse.set(Layer::Known, gx, gy, true);
                }
                Note::GaveUp {
                    seg,
                    cover,
                    stalled,
                    last_end,
                } => self.gave_up(seg, cover, stalled, last_end),
                Note::Bumped {
                    at_us,
                    pose,
                    bearing_mrad,
                } => self.bumped(at_us, pose, bearing_mrad),
                Note::Stalled { at_us, pose, left } => self.wheel_stalled(at_us, pose, left),
            }
        }
    }

    /// Control gave up `seg`: its cells go back for a later pass, or after
    /// repeated stalls its planning cell is marked blocked.
    fn gave_up(&mut self, seg: SubPath, cover: bool, stalled: bool, last_end: Option<(i32, i32)>) {
        if !stalled {
            self.give_up(seg, cover, last_end);
            return;
        }
        let m = &mut *self.m;
        if m.phase == Phase::Cover {
            let (gx, gy) = cspace::coarse_of(self.p.map, m.cfg.plan_cell_mm, seg.to.0, seg.to.1);
            if self.p.coarse.set_obstacle(gx, gy, true).is_ok() {
                m.counters.blocked_cells += 1;
            }
            m.note_coarse_set(gx, gy);
        }
    }

    /// A cleaning sub-path the robot could not drive: its cells go back to
    /// the planner (coverage) or the edge pass, to be tried again later in
    /// the phase, up to [`MAX_RETRIES`] per mission. A cell goes back even
    /// when the coarse grid reads it blocked now: what stopped the robot is
    /// often a person mapped on it (unknown mode), and a cell kept
    /// "covered" under them was never cleaned (the studio with 3 people,
    /// realistic noise, seed 1 lost a 0.4 m strip along a whole wall:
    /// 84.3 % covered, 95.8 % with the cells handed back).
    fn give_up(&mut self, seg: SubPath, cover: bool, last_end: Option<(i32, i32)>) {
        let m = &mut *self.m;
        if !cover || m.reopens >= MAX_RETRIES {
            return;
        }
        if m.phase == Phase::Edge {
            // The edge pass retries at most a tenth as often, and a
            // place only so often ([`EDGE_REOPENS_PER_PLACE`]).
            let again = m.edge_give_ups.count(seg.to);
            if m.edge_reopens >= MAX_RETRIES / 10 || again > EDGE_REOPENS_PER_PLACE {
                return;
            }
            m.edge_reopens += 1;
        }
        let len = dist_mm(seg.from, seg.to);
        let mut any = false;
        match m.phase {
            Phase::Cover => {
                let cell = m.cfg.plan_cell_mm;
                let steps = (len / 100).max(1);
                for k in 0..=steps {
                    let (x, y) = lerp_mm(seg.from, seg.to, k, steps);
                    let (gx, gy) = cspace::coarse_of(self.p.map, cell, x, y);
                    any |= self.reopen_coarse(gx, gy);
                }
                if any {
                    self.resume_planner(last_end.unwrap_or(seg.to));
                }
            }
            Phase::Edge => {
                let steps = (len / 25).max(1);
                for k in 0..=steps {
                    let (x, y) = lerp_mm(seg.from, seg.to, k, steps);
                    let (cx, cy) = self.p.map.cell_of(x, y);
                    any |= reopen_contour_near(self.p.fine, cx, cy);
                }
                if any {
                    let at = m.edge.position();
                    m.edge.reopen(at);
                }
            }
            _ => {}
        }
        if any {
            self.m.reopens += 1;
            self.m.counters.retried += 1;
        }
    }

    /// A planning cell the planner took as covered and the robot's centre
    /// never crossed goes back to the planner; true when it did.
    fn reopen_coarse(&mut self, gx: i32, gy: i32) -> bool {
        let g = &mut *self.p.coarse;
        if g.get(Layer::Known, gx, gy) || !g.get(Layer::Covered, gx, gy) {
            return false;
        }
        let _ = g.set(Layer::Covered, gx, gy, false);
        if let Some(c) = Cell::from_xy(gx, gy) {
            self.p.planner.add_point(g, c);
        }
        true
    }

    /// Every planning cell taken as covered and never driven goes back to
    /// the planner ([`Self::reopen_coarse`]); how many did. One pass over
    /// the planning grid (a few thousand cells).
    pub(super) fn hand_back_undriven(&mut self) -> u32 {
        let (w, h) = (self.p.coarse.width() as i32, self.p.coarse.height() as i32);
        let mut n = 0;
        for gy in 0..h {
            for gx in 0..w {
                if self.p.coarse.is_free(gx, gy) && self.reopen_coarse(gx, gy) {
                    n += 1;
                }
            }
        }
        n
    }

    /// Cells went back to the planner: it plans again, from the planning
    /// cell of `at` (where the robot will be).
    pub(super) fn resume_planner(&mut self, at: (i32, i32)) {
        let (gx, gy) = cspace::coarse_of(self.p.map, self.m.cfg.plan_cell_mm, at.0, at.1);
        if let Some(c) =
            Cell::from_xy(gx, gy).filter(|c| self.p.coarse.is_free(c.x as i32, c.y as i32))
        {
            self.p.planner.reopen(c);
        }
        self.m.planner_done = false;
    }

    /// The fine search found no way to the fed path's goal: it is
    /// skipped. A cleaning goal's planning cell, which the planner took as
    /// covered when it chose it, is kept to be handed back when the
    /// planner finishes ([`Self::hand_back_skipped`]): the robot boxed in
    /// a moment by a person must not throw a lane away. The studio, known
    /// map, 1 person, realistic noise, seed 3, with the exact beam walk:
    /// 15 cells of one lane were skipped so while a person stood by the
    /// robot, and left unswept (96.64 % covered). Known mode only: in
    /// unknown mode a goal with no way to it is mostly one seen through a
    /// gap in a map still growing, which the planner's own abandoned goals
    /// and their late retry cover (handing those back too was measured
    /// with two other give-backs: the real homes' unknown-mode coverage
    /// fell from 96.16 to 95.46 %).
    pub(super) fn skip_goal(&mut self, f: &Feed) {
        let m = &mut *self.m;
        m.counters.skipped += 1;
        if !f.cover || m.phase != Phase::Cover || m.cfg.mode != MapMode::Known {
            return;
        }
        let to = f.then.unwrap_or(f.from);
        let (gx, gy) = cspace::coarse_of(self.p.map, m.cfg.plan_cell_mm, to.0, to.1);
        if let Some(c) = Cell::from_xy(gx, gy) {
            if !m.skipped_goals.contains(&c) {
                let _ = m.skipped_goals.push(c);
            }
        }
    }

    /// The planner finished: the cleaning goals skipped since go back to
    /// it (those the robot's centre has crossed since excepted), like the
    /// goals it gave up itself ([`crate::coverage::Planner::retry_abandoned`]),
    /// within the same two rounds. How many went back.
    pub(super) fn hand_back_skipped(&mut self, at: Cell) -> u32 {
        let skipped = core::mem::take(&mut self.m.skipped_goals);
        let mut n = 0;
        for c in skipped.iter() {
            n += u32::from(self.reopen_coarse(c.x as i32, c.y as i32));
        }
        if n > 0 {
            self.p.planner.reopen(at);
            self.m.planner_done = false;
        }
        n
    }

    /// Every cleaning sub-path still queued goes back for a later pass
    /// ([`Self::give_up`]), and a cleaning move to `tail` after them (a
    /// detour still being fed).
    pub(super) fn put_back_queue(&mut self, tail: Option<(i32, i32)>) {
        let m = &mut *self.m;
        let none = SubPath {
            from: (0, 0),
            to: (0, 0),
        };
        let mut dropped = [(none, false); QUEUE + 1];
        let mut n = 0;
        for (slot, item) in dropped.iter_mut().zip(m.queue.iter()) {
            *slot = item;
            n += 1;
        }
        let last_end = m.queue.last_end();
        if let (Some(from), Some(to), Some(slot)) = (last_end, tail, dropped.get_mut(n)) {
            *slot = (SubPath { from, to }, true);
            n += 1;
        }
        for &(seg, c) in dropped.iter().take(n) {
            self.give_up(seg, c, last_end);
        }
    }

    /// The guard has held the robot: the leg ahead runs into something the
    /// plan did not know of (a wall first seen now, or the pose drifted).
    /// Drops the queue and plans a fresh fine-map path from where the robot
    /// stands to where the queue ended; the same target given up after
    /// three tries. On the way home giving up is not failing: the way home
    /// is planned again from scratch (the Return phase's own tries,
    /// [`super::RETURN_TRIES`] in all), so a person standing a few seconds
    /// in the corridor to the dock does not strand the robot.
    pub(super) fn replan_leg(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        m.guard_block_since = None;
        let cover = m.queue.front().is_some_and(|(_, c)| c);
        let target = m.feed.and_then(|f| f.then).or(m.queue.last_end());
        self.put_back_queue(None);
        let m = &mut *self.m;
        m.feed = None;
        let here = (pose.x_mm, pose.y_mm);
        m.queue.reset(here);
        m.subpath_since_us = now_us;
        m.counters.replans += 1;
        let Some(t) = target else {
            return;
        };
        if m.replan_target == Some(t) {
            m.replan_count += 1;
        } else {
            m.replan_target = Some(t);
            m.replan_count = 1;
        }
        if m.replan_count > 3 {
            m.counters.skipped += 1;
            m.replan_count = 0;
            if m.phase == Phase::Return || m.phase == Phase::ReturnSearch {
                // An empty queue in Return: the next step plans the way
                // home again, or fails after the last try.
                m.phase = Phase::Return;
            }
            return;
        }
        if m.phase == Phase::ReturnSearch || m.phase == Phase::Return {
            m.phase = Phase::ReturnSearch;
        }
        self.detour(here, t, cover);
    }
});

/// Marks the visited contour cells within one cell of (cx, cy) to do
/// again: the edge pass's chords stray up to 40 mm from the contour cells
/// they stand for ([`crate::nav::chord`]), so a sub-path given up reopens
/// its neighbourhood, not only the cells under its line. True when any.
fn reopen_contour_near<const GW: usize>(g: &mut crate::grid::Grid<GW>, cx: i32, cy: i32) -> bool {
    let mut any = false;
    for (dx, dy) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))) {
        let (x, y) = (cx + dx, cy + dy);
        if crate::nav::edge::is_boundary(g, x, y) && g.get(Layer::Covered, x, y) {
            let _ = g.set(Layer::Covered, x, y, false);
            any = true;
        }
    }
    any
}
