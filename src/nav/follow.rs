//! Path following (seed 002 §3, ALGORITHMS.md): the planner's waypoints are
//! merged into straight sub-paths split at the turning points; on each
//! sub-path the robot first rotates in place toward it, then drives
//! straight with heading and cross-track correction (it aims at a point a
//! look-ahead distance further along the line), slowing before the end.
//!
//! World frame: mm, x east, y north; headings in mrad, counter-clockwise.

use crate::math::angle::atan2_urad;
use crate::robot::odometry::Pose;
use heapless::Deque;

/// A straight sub-path, world mm.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SubPath {
    /// Start.
    pub from: (i32, i32),
    /// End.
    pub to: (i32, i32),
}

/// Follower tuning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FollowParams {
    /// Cruise speed, mm/s.
    pub cruise_mm_s: i32,
    /// Slowest approach speed, mm/s.
    pub min_mm_s: i32,
    /// Heading error above which the robot stops and turns in place, mrad.
    pub turn_in_place_mrad: i32,
    /// Turn rate per heading error, (mrad/s) per mrad, ×1000.
    pub k_heading_x1000: i32,
    /// Largest turn rate, mrad/s.
    pub max_w_mrad_s: i32,
    /// Look-ahead along the line for the aim point, mm.
    pub lookahead_mm: i32,
    /// Distance from the end that counts as arrived, mm.
    pub arrive_mm: i32,
    /// Deceleration used to slow before the end, mm/s².
    pub decel_mm_s2: i32,
}

/// Defaults for a 0.3 m/s cleaning run.
pub const DEFAULT_FOLLOW: FollowParams = FollowParams {
    cruise_mm_s: 300,
    min_mm_s: 40,
    turn_in_place_mrad: 250,
    k_heading_x1000: 2500,
    max_w_mrad_s: 1200,
    lookahead_mm: 250,
    arrive_mm: 25,
    decel_mm_s2: 400,
};

/// What to do now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FollowCmd {
    /// Drive with these velocities.
    Drive {
        /// Linear, mm/s.
        v_mm_s: i32,
        /// Angular, mrad/s.
        w_mrad_s: i32,
    },
    /// The end of the sub-path is reached.
    Arrived,
}

fn wrap_urad(a: i64) -> i64 {
    let t = a.rem_euclid(6_283_185);
    if t > 3_141_593 {
        t - 6_283_185
    } else {
        t
    }
}

/// Signed cross-track error (mm, positive left of the line) and the
/// distance left to the end along it (mm).
pub fn track_errors(seg: &SubPath, x_mm: i32, y_mm: i32) -> (i64, i64) {
    let (dx, dy) = (
        (seg.to.0 - seg.from.0) as i64,
        (seg.to.1 - seg.from.1) as i64,
    );
    let (px, py) = ((x_mm - seg.from.0) as i64, (y_mm - seg.from.1) as i64);
    let len = crate::math::cost::isqrt_round_u64((dx * dx + dy * dy) as u64) as i64;
    if len == 0 {
        let d = crate::math::cost::isqrt_round_u64((px * px + py * py) as u64) as i64;
        return (0, d);
    }
    let along = (px * dx + py * dy) / len;
    let cross = (dx * py - dy * px) / len;
    (cross, len - along)
}

/// One control step on a sub-path from the estimated pose.
pub fn follow(p: &FollowParams, seg: &SubPath, pose: &Pose) -> FollowCmd {
    let (_, remaining) = track_errors(seg, pose.x_mm, pose.y_mm);
    let (ex, ey) = ((seg.to.0 - pose.x_mm) as i64, (seg.to.1 - pose.y_mm) as i64);
    let dist_end = crate::math::cost::isqrt_round_u64((ex * ex + ey * ey) as u64) as i64;
    if dist_end <= p.arrive_mm as i64 || remaining <= 0 {
        return FollowCmd::Arrived;
    }
    // Aim point: the projection on the line plus the look-ahead, clamped to
    // the end, so the robot converges onto the line as it drives.
    let (dx, dy) = (
        (seg.to.0 - seg.from.0) as i64,
        (seg.to.1 - seg.from.1) as i64,
    );
    let len = crate::math::cost::isqrt_round_u64((dx * dx + dy * dy) as u64).max(1) as i64;
    let ahead = (len - remaining + p.lookahead_mm as i64).min(len);
    let aim = (
        seg.from.0 as i64 + dx * ahead / len,
        seg.from.1 as i64 + dy * ahead / len,
    );
    let (ax, ay) = (aim.0 - pose.x_mm as i64, aim.1 - pose.y_mm as i64);
    let target = if ax * ax + ay * ay < 100 {
        atan2_urad(ey, ex)
    } else {
        atan2_urad(ay, ax)
    };
    let err_urad = wrap_urad(target - pose.theta_mrad as i64 * 1000);
    let err_mrad = (err_urad / 1000) as i32;
    let w = (err_mrad as i64 * p.k_heading_x1000 as i64 / 1000)
        .max(-(p.max_w_mrad_s as i64))
        .min(p.max_w_mrad_s as i64) as i32;
    if err_mrad.abs() > p.turn_in_place_mrad {
        return FollowCmd::Drive {
            v_mm_s: 0,
            w_mrad_s: w,
        };
    }
    // v² = 2·a·d: slow down to stop at the end.
    let v_stop =
        crate::math::cost::isqrt_u64((2 * p.decel_mm_s2 as i64 * dist_end).max(0) as u64) as i32;
    // max/min, not clamp: no assert on the parameters' order.
    let v = v_stop.max(p.min_mm_s).min(p.cruise_mm_s);
    FollowCmd::Drive {
        v_mm_s: v,
        w_mrad_s: w,
    }
}

/// Merges waypoints into straight sub-paths: a waypoint continuing the last
/// one's direction (and of the same kind) extends it; a turn starts a new
/// sub-path. Holds at most `CAP` sub-paths in a `heapless::Deque` (push
/// returns false when full).
#[derive(Clone, Debug)]
pub struct SubPaths<const CAP: usize> {
    items: Deque<(SubPath, bool), CAP>,
    last_end: Option<(i32, i32)>,
}

impl<const CAP: usize> Default for SubPaths<CAP> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const CAP: usize> SubPaths<CAP> {
    /// An empty queue.
    pub const fn new() -> Self {
        Self {
            items: Deque::new(),
            last_end: None,
        }
    }

    /// Empties the queue and sets where the next sub-path starts.
    pub fn reset(&mut self, at: (i32, i32)) {
        self.items.clear();
        self.last_end = Some(at);
    }

    /// Number of sub-paths queued.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The current sub-path and whether it is a cover move.
    pub fn front(&self) -> Option<(SubPath, bool)> {
        self.items.front().copied()
    }

    /// Replaces the current sub-path (rejoining it from elsewhere).
    pub fn replace_front(&mut self, seg: SubPath) {
        if let Some(slot) = self.items.front_mut() {
            slot.0 = seg;
        }
    }

    /// The end of the last queued sub-path (where the next one starts).
    pub fn last_end(&self) -> Option<(i32, i32)> {
        self.last_end
    }

    /// The queued sub-paths, current first, with their kinds.
    pub fn iter(&self) -> impl Iterator<Item = (SubPath, bool)> + '_ {
        self.items.iter().copied()
    }

    /// Drops the current sub-path.
    pub fn pop(&mut self) {
        self.items.pop_front();
    }

    /// Adds a waypoint (world mm); `cover` tags cleaning moves. A waypoint
    /// collinear with, same direction as and same kind as the last queued
    /// sub-path (other than the one being driven) extends it.
    pub fn push(&mut self, to: (i32, i32), cover: bool) -> bool {
        let Some(from) = self.last_end else {
            self.last_end = Some(to);
            return true;
        };
        if from == to {
            return true;
        }
        if self.items.len() >= 2 {
            if let Some((last, kind)) = self.items.back_mut() {
                let (ux, uy) = (
                    (last.to.0 - last.from.0) as i64,
                    (last.to.1 - last.from.1) as i64,
                );
                let (vx, vy) = ((to.0 - last.to.0) as i64, (to.1 - last.to.1) as i64);
                if *kind == cover && ux * vy - uy * vx == 0 && ux * vx + uy * vy > 0 {
                    last.to = to;
                    self.last_end = Some(to);
                    return true;
                }
            }
        }
        if self.items.push_back((SubPath { from, to }, cover)).is_err() {
            return false;
        }
        self.last_end = Some(to);
        true
    }
}
