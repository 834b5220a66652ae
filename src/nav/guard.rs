//! The safety guard: the last word on the linear speed, every control tick,
//! from the latest lidar points alone (so it holds whatever the map or the
//! odometry believe).
//!
//! A disc of radius r driving straight ahead hits a point (x, y) of the
//! robot frame (x forward, y left) with |y| < r after advancing
//! x − √(r² − y²). The smallest such distance over the points ahead is the
//! free distance; the speed is capped so the robot can brake to a stop
//! `reserve` short of it: v ≤ √(2·a·(free − reserve)). Backing up is
//! checked the same way behind. Turning in place cannot hit anything (the
//! body is a disc), so the turn rate is never capped.

use crate::math::cost::isqrt_u64;

/// Guard tuning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GuardParams {
    /// Body radius plus the lateral margin of the swept corridor, mm.
    pub radius_mm: i32,
    /// Braking deceleration assumed, mm/s².
    pub brake_mm_s2: i32,
    /// Distance kept in hand when stopped, mm.
    pub reserve_mm: i32,
    /// Speeds below this are rounded to a stop, mm/s.
    pub creep_mm_s: i32,
    /// Extra corridor width and reserve for points the map does not
    /// explain (they may move: a person walks 100 mm while the lidar comes
    /// round), mm.
    pub moving_margin_mm: i32,
    /// The range noise (1 σ, mm) of points the map explains (walls), when
    /// the pose is corrected against that map. A hit within 2.5 σ of a
    /// wall cell stands for that cell's wall point (`mission::lidar::Hit`,
    /// no range noise), and the escape judges mapped points this much
    /// closer in. The guard's corridor no longer narrows by it: wall
    /// points are exact, and the other mapped hits are walls the map holds
    /// weakly, judged at full width ([`MappedFree`]).
    pub mapped_slack_mm: i32,
}

/// Free distance (mm) along the robot's forward (`forward`) or backward
/// axis before the body touches one of `points` (robot frame, mm);
/// `i32::MAX` when nothing is in the way. Points already inside the
/// corridor's swept front count as 0.
///
/// The distance to the *second* nearest point is used: a real obstacle
/// returns many points, while a lone range-noise outlier (the LD06 is good
/// to about ±10 mm) beside a wall the robot passes must not stop it. A
/// single stray point can therefore be ignored; anything as thin as a
/// chair leg still returns two or more points within a metre.
pub fn free_distance_mm(
    points: impl Iterator<Item = (i32, i32)>,
    radius_mm: i32,
    forward: bool,
) -> i32 {
    let mut f = FreeDistance::new(radius_mm, forward);
    for p in points {
        f.push(p);
    }
    f.result()
}

/// [`free_distance_mm`] fed one point at a time, so one pass over
/// the lidar ring can serve several corridors (the control tick checks
/// two headings for two classes of points).
#[derive(Clone, Copy, Debug)]
pub struct FreeDistance {
    r: i64,
    forward: bool,
    first: i64,
    second: i64,
}

impl FreeDistance {
    /// An empty corridor of half-width `radius_mm`, ahead (`forward`) or
    /// behind.
    pub fn new(radius_mm: i32, forward: bool) -> Self {
        Self {
            r: radius_mm as i64,
            forward,
            first: i32::MAX as i64,
            second: i32::MAX as i64,
        }
    }

    /// One point (robot frame, mm).
    pub fn push(&mut self, (x, y): (i32, i32)) {
        let (x, y) = (if self.forward { x as i64 } else { -(x as i64) }, y as i64);
        // x − r bounds d from below (the half chord is at most r): a
        // point that far cannot be among the two nearest, and its square
        // root is skipped (most of a room's points).
        if x <= 0 || y.abs() >= self.r || x - self.r >= self.second {
            return;
        }
        let half_chord = isqrt_u64((self.r * self.r - y * y) as u64) as i64;
        let d = (x - half_chord).max(0);
        if d < self.first {
            self.second = self.first;
            self.first = d;
        } else if d < self.second {
            self.second = d;
        }
    }

    /// The free distance: to the second nearest point, `i32::MAX` when
    /// fewer than two are in the way.
    pub fn result(&self) -> i32 {
        self.second as i32
    }

    /// The free distance to the nearest point, `i32::MAX` when none is in
    /// the way: for points that are certain (a blocking map cell's
    /// outline), where one is enough.
    pub fn nearest(&self) -> i32 {
        self.first as i32
    }
}

/// The free distance for the points the map explains, judged at full
/// width: a hit on a wall cell's square by the wall point it stands for
/// (no range noise), every other mapped hit as measured. The two kinds
/// are counted apart, each needing two points of its own, so one stray
/// hit and one wall point do not make an obstacle together.
///
/// Why the other hits at full width: such a hit lies more than 2.5 σ from
/// every occupied cell, so it is not noise off a known wall but a wall
/// the map holds only weakly (a diagonal wall's staircase, its cells
/// short of the occupied threshold; a wall not yet mapped). Judged a
/// noise σ inside the corridor's edge, as until stop 59, hits 161–166 mm
/// beside the path (z10, unknown mode, seed 1) went uncounted and the
/// body grazed that wall.
#[derive(Clone, Copy, Debug)]
pub struct MappedFree {
    wall: FreeDistance,
    other: FreeDistance,
}

impl MappedFree {
    /// An empty corridor of half-width `radius_mm`, ahead (`forward`) or
    /// behind.
    pub fn new(radius_mm: i32, forward: bool) -> Self {
        let f = FreeDistance::new(radius_mm, forward);
        Self { wall: f, other: f }
    }

    /// One point (robot frame, mm): a wall point (`on_wall`) or a hit
    /// that stands for itself.
    pub fn push(&mut self, p: (i32, i32), on_wall: bool) {
        if on_wall {
            self.wall.push(p);
        } else {
            self.other.push(p);
        }
    }

    /// The nearer of the two kinds' free distances.
    pub fn result(&self) -> i32 {
        self.wall.result().min(self.other.result())
    }
}

/// The linear speed allowed (same sign as `v_mm_s`, never larger in
/// magnitude) given the free distance ahead in the direction of travel.
pub fn limit_speed(p: &GuardParams, v_mm_s: i32, free_mm: i32) -> i32 {
    if v_mm_s == 0 {
        return 0;
    }
    let room = (free_mm as i64 - p.reserve_mm as i64).max(0);
    let cap =
        isqrt_u64((2 * p.brake_mm_s2.max(0) as i64 * room) as u64).min(i32::MAX as u64) as i32;
    let cap = if cap < p.creep_mm_s { 0 } else { cap };
    v_mm_s.clamp(-cap, cap)
}
