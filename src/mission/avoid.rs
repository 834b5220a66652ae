//! Avoidance (seed 002 §3.1): something the map does not explain in the
//! corridor ahead starts it; the robot waits, then DWA ([`crate::nav::dwa`])
//! steers toward the end of the current straight sub-path, and it rejoins
//! once the way is clear. Given up after `avoid_timeout_us`.

use super::config::MAP_POINTS;
use super::events::EventKind;
use super::lidar::Hit;
use super::{Activity, LocalPlanner, MapMode, Mission, Phase, RING};
use crate::math::cost::dist_mm;
use crate::nav::apf::{self, ApfResult};
use crate::nav::cspace;
use crate::nav::dwa::{self, DwaResult, MAX_OBSTACLES};
use crate::nav::follow::SubPath;
use crate::nav::geometry::{
    foot_on_segment, in_corridor, segment_clear, segment_surely_clear, toward, RobotFrame,
};
use crate::nav::guard::free_distance_mm;
use crate::robot::lidar_map::CellState;
use crate::robot::odometry::Pose;

/// Evidence a cell must hold to make an edge-pass leg stale
/// (`leg_blocked` below): a wall hit again and again (one hit from
/// unknown is [`crate::robot::lidar_map::HIT`] = 3), not the cell in
/// front of a wall's face that flickers across the occupied threshold
/// (2) as noisy returns land in it. The pass runs its contours at the
/// clearance from walls, where one such flicker turned every leg along
/// the wall stale: the leg was planned again, the contour's queued cells
/// given up, and the robot never drove that contour (1c home, unknown
/// mode, realistic noise, 1 person, seed 4: 91.5 % covered, with 10 to
/// 20 cm strips missed along whole walls; at 4, 96.6 %). At 6 (a
/// well-seen wall only) collisions came back.
const EDGE_STALE_EVIDENCE: i8 = 4;

/// How far ahead of the robot's foot the leg is checked against the
/// growing map, mm (`leg_blocked` below). 300 mm was tried: the same
/// coverage, and 2 contacts of the 10 left instead of none.
const STALE_LOOK_MM: i64 = 800;

sized_impl!([] {
    /// Starts and ends avoidance; runs DWA while avoiding.
    pub(super) fn watch_corridor(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        let Some((seg, _)) = m.queue.front() else {
            m.activity = Activity::Follow;
            return;
        };
        let here = (pose.x_mm, pose.y_mm);
        let (reach, total, ahead) = m.corridor(here, seg.to);
        match m.activity {
            Activity::BackOff { .. } => {}
            Activity::Follow => {
                let unexplained = m
                    .points_where(false)
                    .filter(|&q| in_corridor(here, ahead, q, reach))
                    .take(2)
                    .count();
                if unexplained >= 2 {
                    m.activity = Activity::Avoid;
                    m.avoid_since_us = now_us;
                    m.counters.avoidance_events += 1;
                    m.dwa_cmd = (0, 0);
                } else if self.leg_blocked(here, &seg) {
                    self.m.counters.stale_legs += 1;
                    self.replan_leg(now_us, pose);
                }
            }
            Activity::Avoid => {
                if total < 60 {
                    // Close enough: the sub-path is done. The next one
                    // starts up to 60 mm from here (z10, unknown,
                    // realistic, seeds 3 and 7: followed from 32 mm beside
                    // its start, an edge chord ran the body onto a
                    // diagonal wall's corner).
                    m.queue.pop();
                    if let Some((next, _)) = m.queue.front() {
                        let to = next.to;
                        self.rejoin(now_us, pose, to);
                    } else {
                        m.activity = Activity::Follow;
                        m.subpath_since_us = now_us;
                    }
                    return;
                }
                // Rejoin once nothing unmapped lies in the corridor and the
                // guard would let the robot drive 250 mm straight toward the
                // end (the guard's own rule, so it does not hold it again).
                let unexplained = m
                    .points_where(false)
                    .any(|q| in_corridor(here, ahead, q, reach));
                let free = m.free_toward(here, seg.to);
                if !unexplained && free >= 250.min(total) {
                    let to = seg.to;
                    self.rejoin(now_us, pose, to);
                    return;
                }
                let waited = now_us.saturating_sub(m.avoid_since_us);
                if waited > m.cfg.avoid_timeout_us {
                    m.activity = Activity::Follow;
                    self.replan_leg(now_us, pose);
                    return;
                }
                if waited < m.cfg.avoid_wait_us {
                    // First wait: people usually walk on.
                    m.dwa_cmd = (0, 0);
                    return;
                }
                self.local_step(now_us, pose, seg.to);
            }
        }
    }

    /// Ends avoidance toward the front sub-path's end `to`: straight from
    /// here when the map allows the body's sweep there, else by a fresh
    /// path from here ([`Self::replan_leg`]).
    fn rejoin(&mut self, now_us: u64, pose: &Pose, to: (i32, i32)) {
        let m = &mut *self.m;
        m.activity = Activity::Follow;
        m.subpath_since_us = now_us;
        let here = (pose.x_mm, pose.y_mm);
        if segment_clear(self.p.map, here, to, m.cfg.sweep_mm()) {
            m.queue.replace_front(SubPath { from: here, to });
        } else {
            self.replan_leg(now_us, pose);
        }
    }

    /// The map now blocks the edge of the leg ahead (unknown mode). Every
    /// queued sub-path was clear of occupied cells by `radius + margin / 2`
    /// when it was queued ([`Self::enqueue`], the edge pass's chords), but
    /// in unknown mode the map grows under the plan, and the end of a thin
    /// wall flickers between free and occupied as rays graze its corner:
    /// a lane queued while a door jamb read free ran the body into it (5 of
    /// the 7 wall contacts of one suite row, the office). The guard does
    /// not stop that: a corner at the corridor's edge returns one or two
    /// points, and it ignores a lone point.
    ///
    /// The same test is made again on the planned line, from the robot's
    /// foot on it (so following error does not count) over the next
    /// [`STALE_LOOK_MM`], and it counts only what grazes the body:
    /// something farther than half the radius from the line. What stands
    /// across it (a person, mapped like a wall in unknown mode) is left to
    /// avoidance and the guard. Known mode is left alone: its plans are
    /// made on the prior, which does not change, and checking them there
    /// too (people across the line included) replanned around every step
    /// of the people, for no contact saved and up to 4 points of coverage
    /// lost (the studio with 3 people). In the edge pass only cells sure
    /// to block count ([`EDGE_STALE_EVIDENCE`]). Work: two
    /// [`segment_clear`] of at most 800 mm.
    fn leg_blocked(&self, here: (i32, i32), seg: &SubPath) -> bool {
        let cfg = &self.m.cfg;
        if cfg.mode != MapMode::Unknown || self.m.near_dock(here) {
            return false;
        }
        let foot = foot_on_segment(seg.from, seg.to, here);
        let end = toward(foot, seg.to, STALE_LOOK_MM);
        let (map, r) = (&*self.p.map, cfg.sweep_mm());
        let across = (cfg.radius_mm / 2) as i64;
        let grazes = if self.m.phase == Phase::Edge {
            !segment_surely_clear(map, foot, end, r, EDGE_STALE_EVIDENCE)
        } else {
            !segment_clear(map, foot, end, r)
        };
        grazes && segment_clear(map, foot, end, across)
    }

    /// One cycle of the local planner the configuration names (DWA or the
    /// potential field) toward `goal_world`, among the nearest obstacles.
    pub(super) fn local_step(&mut self, now_us: u64, pose: &Pose, goal_world: (i32, i32)) {
        let mut obs = [(0i32, 0i32); MAX_OBSTACLES];
        let k = self.nearest_obstacles(pose, &mut obs);
        let obs = obs.get(..k).unwrap_or(&[]);
        let m = &mut *self.m;
        let goal = RobotFrame::of(pose).to_robot(goal_world);
        let turn = || {
            // Turn in place toward the goal (a disc cannot hit anything
            // turning in place).
            let bearing = crate::math::angle::atan2_mrad(goal.1, goal.0);
            (0, if bearing >= 0 { 500 } else { -500 })
        };
        m.dwa_cmd = match m.cfg.local {
            LocalPlanner::Dwa => match dwa::plan(&m.cfg.dwa, m.cmd.0.max(0), m.cmd.1, goal, obs) {
                DwaResult::Command {
                    v_mm_s, w_mrad_s, ..
                } => (v_mm_s, w_mrad_s),
                DwaResult::NoAdmissible => {
                    m.counters.dwa_no_admissible += 1;
                    turn()
                }
            },
            LocalPlanner::Apf => match apf::plan(&m.cfg.apf, goal, obs) {
                ApfResult::Command {
                    v_mm_s, w_mrad_s, ..
                } => (v_mm_s, w_mrad_s),
                ApfResult::LocalMinimum { .. } => {
                    // A new minimum: 150 mm or more from the last one.
                    let here = (pose.x_mm, pose.y_mm);
                    if m.apf_minimum.is_none_or(|p| dist_mm(p, here) >= 150) {
                        m.apf_minimum = Some(here);
                        m.counters.apf_minima += 1;
                        let (x_mm, y_mm) = here;
                        m.events.push(now_us, EventKind::LocalMinimum { x_mm, y_mm });
                    }
                    turn()
                }
            },
        };
    }

    /// The obstacle points a local planner weighs, robot frame, nearest
    /// first into `obs`; returns how many.
    fn nearest_obstacles(&self, pose: &Pose, obs: &mut [(i32, i32); MAX_OBSTACLES]) -> usize {
        let m = &*self.m;
        // The points stream into the nearest-k selection: no buffer of all
        // of them (it was 4.6 KB of stack, which overflowed the
        // firmware's in the studio at 261 s).
        // Unmapped points (maybe people) are moved closer by the guard's
        // extra margin, so DWA keeps the berth the guard will insist on.
        let extra = m.cfg.guard.moving_margin_mm as i64;
        let frame = RobotFrame::of(pose);
        let ring = m.lidar.ring.as_slice();
        let lidar = ring.iter().map(|&Hit { x, y, mapped, .. }| {
            let (rx, ry) = frame.to_robot((x, y));
            if mapped {
                return (rx, ry);
            }
            let d = crate::math::cost::isqrt_u64(
                (rx as i64 * rx as i64 + ry as i64 * ry as i64) as u64,
            )
            .max(1) as i64;
            let k = (d - extra).max(0);
            ((rx as i64 * k / d) as i32, (ry as i64 * k / d) as i32)
        });
        // Nearby grid obstacles (known mode: the prior map's walls; the
        // rims of no-go zones and virtual walls), as
        // many as fill RING + MAP_POINTS with the ring's.
        let map = &*self.p.map;
        let (cx, cy) = map.cell_of(pose.x_mm, pose.y_mm);
        let k = (600 / map.res_mm().max(1)) as i32;
        let grid = (cy - k..=cy + k)
            .flat_map(|y| (cx - k..=cx + k).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                map.state(x, y) == CellState::Occupied || cspace::zone_rim(map, x, y)
            })
            .map(|(x, y)| frame.to_robot(cspace::fine_centre_mm(map, x, y)))
            .take((RING + MAP_POINTS).saturating_sub(ring.len().min(RING)));
        crate::math::select::smallest_k_of(lidar.take(RING).chain(grid), obs, |p| {
            p.0 as i64 * p.0 as i64 + p.1 as i64 * p.1 as i64
        })
    }
});

impl Mission {
    /// The corridor checked ahead of the robot toward `to`: its half-width
    /// (mm), the distance to `to` (mm), and where it ends (at most
    /// `lookahead_mm` on).
    pub(super) fn corridor(&self, here: (i32, i32), to: (i32, i32)) -> (i64, i64, (i32, i32)) {
        let reach = (self.cfg.radius_mm + self.cfg.corridor_mm) as i64;
        let total = dist_mm(here, to);
        let ahead = toward(here, to, self.cfg.lookahead_mm as i64);
        (reach, total, ahead)
    }

    /// How far the guard would let the robot drive from `here` straight
    /// toward `target` (after its reserves), mm.
    pub(super) fn free_toward(&self, here: (i32, i32), target: (i32, i32)) -> i64 {
        let toward =
            crate::math::angle::atan2_urad((target.1 - here.1) as i64, (target.0 - here.0) as i64);
        let facing = Pose {
            x_mm: here.0,
            y_mm: here.1,
            theta_mrad: (toward / 1000) as i32,
        };
        let g = self.cfg.guard;
        let frame = RobotFrame::of(&facing);
        let fs = free_distance_mm(
            self.points_where(true).map(|q| frame.to_robot(q)),
            g.radius_mm,
            true,
        ) as i64
            - g.reserve_mm as i64;
        let fm = free_distance_mm(
            self.points_where(false).map(|q| frame.to_robot(q)),
            g.radius_mm + g.moving_margin_mm,
            true,
        ) as i64
            - (g.reserve_mm + g.moving_margin_mm) as i64;
        fs.min(fm)
    }
}
