//! The planning step (10 Hz): the hand-off replayed, the battery, the
//! guard's hold, and the one dispatch on the phase; the self-test.

use super::{Activity, Fault, MapMode, Phase};
use crate::math::cost::dist_mm;
use crate::nav::cspace;
use crate::nav::geometry::segment_clear;
use crate::nav::keep_off::NearWalls;

/// A move held by the guard that ends within this of the robot and is not
/// clear on the map is skipped, not planned again, mm.
const SKIP_SHORT_MM: i64 = 150;

/// Holds in a row of the same short move before it is skipped.
const SKIP_AFTER_HOLDS: u8 = 3;
use crate::robot::odometry::Pose;

sized_impl!([] {
    /// The body of [`Mission::begin`].
    pub(super) fn begin(&mut self, start: Pose) {
        // No `*self.m = Mission::new(cfg)` here: that builds the whole
        // executive (about 20 KB) on the stack, more than the firmware's
        // stack has (found by the processor-in-the-loop run). A mission
        // begins on a fresh executive (see `Mission::begin`).
        let cfg = self.m.cfg;
        let m = &mut *self.m;
        m.drive
            .odom
            .set_pose(start.x_mm, start.y_mm, start.theta_mrad);
        m.drive.map_h_mm = self.p.map.height() as i64 * self.p.map.res_mm() as i64;
        m.start = start;
        self.p.planner.set_kind(cfg.kind);
        if cfg.mode == MapMode::Known {
            self.p.map.freeze_prior();
        } else if cfg.prior_saved {
            self.p.map.thaw_prior();
        }
        if cfg.localize {
            self.p.matcher.pyramid.build(self.p.map, cfg.mode == MapMode::Known);
        }
        let r = (cfg.radius_mm + cfg.margin_mm) as u32;
        let ok = cspace::size_coarse(self.p.map, self.p.coarse, cfg.plan_cell_mm).is_ok()
            && cspace::update_coarse(self.p.map, self.p.coarse, cfg.plan_cell_mm, r, false).is_ok();
        if ok && cfg.mode == MapMode::Known {
            self.split_rooms();
        }
        let m = &mut *self.m;
        m.phase = if ok {
            Phase::SelfTestScan { since_us: 0 }
        } else {
            Phase::Failed(Fault::Capacity)
        };
    }

    /// The body of [`Mission::plan`]: replays the hand-off, then steps.
    pub(super) fn plan(&mut self, now_us: u64) {
        let m = &mut *self.m;
        m.plan_due_us = now_us + m.cfg.plan_period_us;
        m.counters.plan_steps += 1;
        self.drain();
        let pose = self.m.drive.odom.pose();
        // A tenth of a second at cruise speed (30 mm) beyond what steers.
        let c = &self.m.cfg;
        let keep_mm = c.keep_off.keep_mm.max(c.keep_off_transit.keep_mm);
        if keep_mm > 0 {
            let reach = c.radius_mm + keep_mm + 100;
            self.m.near_walls = NearWalls::gather(self.p.map, (pose.x_mm, pose.y_mm), reach);
        }
        self.note_people_near(now_us, &pose);
        self.step(now_us, &pose);
    }

    /// One planning step (10 Hz).
    /// One planning step: the battery, the guard's hold, then the phase's
    /// own work. The one state-machine dispatch of the executive.
    fn step(&mut self, now_us: u64, pose: &Pose) {
        if self.go_home_when_due(now_us, pose) {
            return;
        }
        self.guard_hold(now_us, pose);
        // Relocalised after a kidnap (the leg ahead starts elsewhere), or
        // backed off from a bump (the leg ahead ran into it): plan the leg
        // again once following.
        let following = self.m.activity == Activity::Follow;
        let relocated = core::mem::take(&mut self.m.relocated) && following;
        let bumped = following && core::mem::take(&mut self.m.bump_replan);
        for due in [relocated, bumped] {
            if due && self.m.phase.driving() {
                self.replan_leg(now_us, pose);
            }
        }
        match self.m.phase {
            Phase::SelfTestScan { .. }
            | Phase::SelfTestWheels { .. }
            | Phase::SelfTestSettle { .. } => self.self_test(now_us, pose),
            Phase::Cover => self.cover_step(now_us, pose),
            Phase::Edge => {
                self.trace_lanes(pose);
                self.watch_corridor(now_us, pose);
                if self.feed_path() && self.feed_route() {
                    self.top_up_edge();
                }
            }
            Phase::ReturnSearch | Phase::Return => self.return_step(now_us, pose),
            Phase::Charging { .. } => self.charging_step(now_us, pose),
            Phase::Idle | Phase::Align | Phase::Done | Phase::Failed(_) => {}
        }
    }

    /// Battery: with the charge low, home to charge and resume
    /// ([`super::battery`]); after the cleaning budget (no charge known),
    /// or when asked ([`super::Mission::request_home`]), home for good.
    /// True when it went.
    fn go_home_when_due(&mut self, now_us: u64, pose: &Pose) -> bool {
        let m = &mut *self.m;
        if !matches!(m.phase, Phase::Cover | Phase::Edge) {
            return false;
        }
        let here = (pose.x_mm, pose.y_mm);
        let dock = (m.start.x_mm, m.start.y_mm);
        if !m.home_requested && m.battery.low(&m.cfg.battery, here, dock, now_us) {
            self.leave_for_charge(pose);
            return true;
        }
        let timed = m.battery.now_pm.is_none();
        let spent = timed && now_us.saturating_sub(m.started_us) > m.cfg.battery_us;
        if !(spent || m.home_requested) {
            return false;
        }
        m.home_requested = false;
        if spent {
            m.counters.battery_returns += 1;
        }
        m.feed = None;
        m.route.clear();
        m.activity = Activity::Follow;
        m.queue.reset((pose.x_mm, pose.y_mm));
        m.fine_is_edge = false;
        self.begin_return(pose);
        true
    }

    /// Held by the guard for a second. If the map says the way on is
    /// clear, what blocks it is not on the map (or the pose drifted): steer
    /// around it on the lidar alone (DWA). If the map has learnt of a wall
    /// across it: plan the leg again; but a move of a few cm the body
    /// cannot make (a route's waypoint just inside a corner, as the map
    /// sees it: routes exist only at the chip's capacity, [`super::route`]),
    /// held [`SKIP_AFTER_HOLDS`] times in a row with its leg
    /// planned again in between, is skipped: the firmware-capacity office
    /// stood 1,500 s in such a loop on its way home. (Skipping it at the
    /// first hold was tried: collisions in the flat suite rose from 9 to
    /// 26 of 36 missions, the next leg from where the robot stood cutting
    /// the corner; at the second, to 17; for any transit at the third, to
    /// 18, a bump loop against a wall.)
    fn guard_hold(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        let driving = m.phase.driving();
        let held = m
            .guard_block_since
            .is_some_and(|t| now_us.saturating_sub(t) > 1_000_000);
        if !driving || m.activity != Activity::Follow || !held {
            return;
        }
        m.guard_block_since = None;
        let here = (pose.x_mm, pose.y_mm);
        let r = m.cfg.sweep_mm();
        match m.queue.front() {
            Some((_, _)) if segment_clear(self.p.map, here, seg_to(&m.queue), r) => {
                m.activity = Activity::Avoid;
                m.avoid_since_us = now_us;
                m.counters.avoidance_events += 1;
                m.dwa_cmd = (0, 0);
            }
            Some((seg, false)) if m.route.holds(seg.to) => {
                let holds = match m.held_to {
                    Some((to, n)) if to == seg.to => n.saturating_add(1),
                    _ => 1,
                };
                if holds >= SKIP_AFTER_HOLDS && dist_mm(here, seg.to) <= SKIP_SHORT_MM {
                    m.held_to = None;
                    m.queue.pop();
                    m.subpath_since_us = now_us;
                    m.counters.skipped += 1;
                } else {
                    m.held_to = Some((seg.to, holds));
                    self.replan_leg(now_us, pose);
                }
            }
            _ => self.replan_leg(now_us, pose),
        }
    }

    /// The self-test phases: lidar revolutions, then a turn in place.
    fn self_test(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        match m.phase {
            Phase::SelfTestScan { since_us } => {
                if m.counters.scans >= 2 {
                    m.phase = Phase::SelfTestWheels {
                        until_us: now_us + 400_000,
                        enc0: m.drive.enc_last,
                    };
                } else if now_us.saturating_sub(since_us) > 3_000_000 {
                    self.fail(Fault::SelfTestLidar);
                }
            }
            Phase::SelfTestWheels { until_us, enc0 } if now_us >= until_us => {
                let dl = m.drive.enc_last.0.wrapping_sub(enc0.0) as i16;
                let dr = m.drive.enc_last.1.wrapping_sub(enc0.1) as i16;
                // Turning left: the left wheel backward, the right forward.
                m.phase = if dl <= -20 && dr >= 20 {
                    Phase::SelfTestSettle {
                        until_us: now_us + 300_000,
                    }
                } else {
                    Phase::Failed(Fault::SelfTestWheels)
                };
            }
            Phase::SelfTestSettle { until_us } if now_us >= until_us => {
                self.start_cover(now_us, pose);
            }
            _ => {}
        }
    }
});

/// Where the front sub-path ends ((0, 0) when the queue is empty).
fn seg_to<const C: usize>(q: &crate::nav::follow::SubPaths<C>) -> (i32, i32) {
    q.front().map(|(s, _)| s.to).unwrap_or((0, 0))
}
