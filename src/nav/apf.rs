//! The artificial potential field as a local planner, next to DWA
//! ([`super::dwa`]): the robot turns toward, and drives along, the sum of an
//! attraction to its sub-goal and a repulsion from every obstacle point
//! near it (Khatib, "Real-time obstacle avoidance for manipulators and
//! mobile robots", IJRR 1986; seed 004's local method, ALGORITHMS.md §5).
//! [`crate::search::apf`] is the same field walked cell by cell on a grid,
//! as a point-to-point baseline; this one steers the robot.
//!
//! **The field** (robot frame, x forward, y left; forces in per-mille of
//! the full attraction):
//! - attraction: the conic well `A·g / max(|g|, d_sat)` toward the goal `g`
//!   (A = 1000), full strength beyond `d_sat`, fading linearly inside it so
//!   the robot slows onto its goal;
//! - repulsion: for each point whose clearance ρ (its distance less the
//!   body's radius) is below ρ0, Khatib's gradient
//!   `k·(1/ρ − 1/ρ0)/ρ²` pointing away from it. In integers it is
//!   `k·(ρ0 − ρ)·R³ / (ρ0·ρ³)` with R = 100 mm, so `k` is the push of a
//!   point 100 mm from the body in the limit ρ0 → ∞; ρ is held at 10 mm
//!   or more.
//! - The points are those DWA gets (the lidar's nearest and the map's
//!   walls nearby, [`super::dwa::MAX_OBSTACLES`] at most), summed: a wall
//!   pushes with every point of it the lidar returns.
//!
//! **The command.** ω turns toward the force's direction α
//! (`ω = k_ω·α`, clamped); v is `v_max·cos α·min(1, |F|)` when |α| is
//! under `drive_mrad`, else 0 (turn in place first). The speed guard of
//! the mission still bounds v, as it bounds DWA's.
//!
//! **Local minima are reported, not hidden.** Where the repulsion cancels
//! the attraction (a wall square across the way, a U-shaped pocket) the
//! force vanishes although the goal is not reached: [`ApfResult::LocalMinimum`]
//! says so, with what force was left. The caller decides what to do (the
//! mission counts it, logs it and turns toward the goal; its avoidance
//! timeout then plans a new way). Seed 004 names this as the method's known
//! weakness; we keep it visible rather than add an escape rule.
//!
//! **Our choices** (the seed gives the formulas only): ρ0 = 300 mm,
//! k = 400, d_sat = 500 mm, a minimum below 150 ‰ of the full attraction
//! (and farther than 100 mm from the goal); the tests show a wall ahead
//! turning the robot, a clear way driven straight, and a pocket reported.

pub use super::dwa::PointMm;
use crate::math::angle::{atan2_mrad, sin_cos_q30};
use crate::math::cost::isqrt_u64;

/// The field's gains and the command's limits (units in the names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ApfParams {
    /// Body radius plus margin, mm: clearances are measured from it.
    pub radius_mm: i32,
    /// ρ0, the reach of the repulsion beyond the body, mm.
    pub reach_mm: i32,
    /// k, the repulsion gain (per-mille of the full attraction, see the
    /// module's doc).
    pub k_rep: i32,
    /// Distance to the goal inside which the attraction fades, mm.
    pub sat_mm: i32,
    /// Below this force (per-mille) short of the goal: a local minimum.
    pub min_force_pm: i32,
    /// Closer than this to the goal, a small force is arrival, mm.
    pub arrive_mm: i32,
    /// Fastest forward speed, mm/s.
    pub v_max_mm_s: i32,
    /// Largest turn rate, mrad/s.
    pub w_max_mrad_s: i32,
    /// Turn gain: mrad/s per rad of heading error.
    pub k_w: i32,
    /// Drive only when the force lies within this angle ahead, mrad.
    pub drive_mrad: i32,
}

/// Our defaults for the 0.33 m robot (the module's doc says why).
pub const DEFAULT_APF: ApfParams = ApfParams {
    radius_mm: 180,
    reach_mm: 300,
    k_rep: 400,
    sat_mm: 500,
    min_force_pm: 150,
    arrive_mm: 100,
    v_max_mm_s: 300,
    w_max_mrad_s: 1000,
    k_w: 1500,
    drive_mrad: 700,
};

/// What the field says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ApfResult {
    /// Drive along the force.
    Command {
        /// Linear velocity, mm/s.
        v_mm_s: i32,
        /// Angular velocity, mrad/s.
        w_mrad_s: i32,
        /// The force's size, per-mille of the full attraction.
        force_pm: i32,
    },
    /// The force vanished short of the goal: a local minimum of the field.
    LocalMinimum {
        /// The force left, per-mille.
        force_pm: i32,
    },
}

/// The field's force at the robot, per-mille of the full attraction
/// (robot frame).
pub fn force(p: &ApfParams, goal: PointMm, obstacles: &[PointMm]) -> (i64, i64) {
    let (gx, gy) = (goal.0 as i64, goal.1 as i64);
    let dg = norm(gx, gy).max(p.sat_mm.max(1) as i64);
    let (mut fx, mut fy) = (1000 * gx / dg, 1000 * gy / dg);
    // Bounded so no product below can overflow: a point counts only
    // within radius + reach ≤ 10 m, and a push is at most k·1000 ≤ 10^8.
    let reach = p.reach_mm.clamp(11, 5000) as i64;
    let radius = p.radius_mm.clamp(0, 5000) as i64;
    let k = p.k_rep.clamp(0, 100_000) as i64;
    for &(ox, oy) in obstacles {
        let (ox, oy) = (ox as i64, oy as i64);
        let d = norm(ox, oy);
        let rho = (d - radius).max(10);
        if rho >= reach || d == 0 {
            continue;
        }
        // k·(ρ0 − ρ)·R³ / (ρ0·ρ³), R = 100 mm: at most k·10^3.
        // reach·ρ³ ≥ 11·10³ and below 2^43: never zero.
        let push = (k * (reach - rho) * 1_000_000)
            .checked_div(reach * rho * rho * rho)
            .unwrap_or(0);
        fx -= push * ox / d;
        fy -= push * oy / d;
    }
    (fx, fy)
}

/// One cycle: the command along the force at the robot, or the local
/// minimum it sits in. `goal` and `obstacles` are in the robot frame, mm.
pub fn plan(p: &ApfParams, goal: PointMm, obstacles: &[PointMm]) -> ApfResult {
    let (fx, fy) = force(p, goal, obstacles);
    let f = norm(fx, fy).min(i32::MAX as i64) as i32;
    let to_goal = norm(goal.0 as i64, goal.1 as i64);
    if f < p.min_force_pm && to_goal > p.arrive_mm as i64 {
        return ApfResult::LocalMinimum { force_pm: f };
    }
    let clamp = |v: i64| v.clamp(-(1 << 30), 1 << 30) as i32;
    let alpha = atan2_mrad(clamp(fy), clamp(fx));
    let w = (p.k_w as i64 * alpha as i64 / 1000) as i32;
    // min/max, not clamp: a negative limit from a bad configuration must
    // not panic.
    let w_mrad_s = w.min(p.w_max_mrad_s).max(-p.w_max_mrad_s);
    let v_mm_s = if alpha.abs() < p.drive_mrad {
        let (_, cos_q30) = sin_cos_q30(alpha as i64 * 1000);
        let v = (p.v_max_mm_s as i64 * cos_q30) >> 30;
        (v * f.min(1000) as i64 / 1000) as i32
    } else {
        0
    };
    ApfResult::Command {
        v_mm_s,
        w_mrad_s,
        force_pm: f,
    }
}

/// |(x, y)|, rounded down. Not `math::cost::dist_mm`: the force's sums
/// exceed `i32`, and squares of full-range `i32` points overflow `i64`.
fn norm(x: i64, y: i64) -> i64 {
    let s = (x as i128 * x as i128 + y as i128 * y as i128).min(u64::MAX as i128);
    isqrt_u64(s as u64) as i64
}
