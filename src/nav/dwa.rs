//! Integer Dynamic Window Approach (Fox, Burgard and Thrun 1997; seed 002
//! §3.1 in ALGORITHMS.md), the local planner that steers around obstacles
//! the map did not have.
//!
//! - Velocities are sampled in mm/s and mrad/s inside the search space
//!   Vr = Vs ∩ Va ∩ Vd: Vs the robot's limits, Vd the window reachable within
//!   one cycle at the acceleration limits, Va the velocities from which the
//!   robot can still stop before the nearest obstacle on that arc
//!   (v² ≤ 2·dist·v̇_brake, and ω² ≤ 2·(dist / r)·ω̇_brake with the distance
//!   turned into an angle over the robot's radius r — our reading of Fox's
//!   angular condition for a differential drive).
//! - Each sample is rolled out as a unicycle over the prediction horizon in
//!   fixed point (positions in µm, heading in µrad, Q30 sin/cos).
//! - Clearance is the smallest distance from the rolled-out centre to any
//!   obstacle point (the latest lidar points in the robot frame plus nearby
//!   grid obstacles, given by the caller), minus the robot's radius; a
//!   trajectory that touches an obstacle is not admissible.
//! - The score is α·heading + β·clearance + γ·velocity with each term
//!   normalised by its largest value over the admissible samples (σ), all in
//!   integers (per-mille). Heading is π minus the angle between the final
//!   heading and the goal as seen from the final position.
//!
//! Work per cycle is bounded: `V_SAMPLES × W_SAMPLES` rollouts of
//! `horizon / step` steps against at most `MAX_OBSTACLES` points. When no
//! sample is admissible, [`DwaResult::NoAdmissible`] says so and the caller
//! stops or rotates in place.

use crate::math::angle::{atan2_urad, sin_cos_q30};

/// Velocity samples (linear).
pub const V_SAMPLES: usize = 7;
/// Velocity samples (angular).
pub const W_SAMPLES: usize = 11;
/// Most obstacle points considered per cycle (the nearest are kept by the
/// caller; see [`nearest_obstacles`]).
pub const MAX_OBSTACLES: usize = 64;

/// DWA parameters (units in the names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DwaParams {
    /// Slowest forward speed, mm/s (0 allows stopping).
    pub v_min_mm_s: i32,
    /// Fastest forward speed, mm/s.
    pub v_max_mm_s: i32,
    /// Largest turn rate, mrad/s.
    pub w_max_mrad_s: i32,
    /// Linear acceleration and braking, mm/s².
    pub acc_mm_s2: i32,
    /// Angular acceleration and braking, mrad/s².
    pub w_acc_mrad_s2: i32,
    /// Control cycle, ms (the window's width).
    pub dt_ms: i32,
    /// Prediction horizon, ms.
    pub horizon_ms: i32,
    /// Rollout step, ms.
    pub step_ms: i32,
    /// Robot radius plus safety margin, mm.
    pub radius_mm: i32,
    /// Clearance beyond which more does not score, mm.
    pub clearance_cap_mm: i32,
    /// Weights (per-mille of the score): heading, clearance, velocity.
    pub alpha: i32,
    /// Clearance weight.
    pub beta: i32,
    /// Velocity weight.
    pub gamma: i32,
}

/// Defaults for our robot (0.33 m disc, 0.5 m/s): seed 002's robot uses
/// v ∈ [0.1, 0.5] m/s, a = 0.5 m/s², ω ∈ [−1, 1] rad/s.
pub const DEFAULT_PARAMS: DwaParams = DwaParams {
    v_min_mm_s: 0,
    v_max_mm_s: 500,
    w_max_mrad_s: 1000,
    acc_mm_s2: 500,
    w_acc_mrad_s2: 2000,
    dt_ms: 100,
    horizon_ms: 2000,
    step_ms: 100,
    radius_mm: 195,
    clearance_cap_mm: 1000,
    alpha: 700,
    beta: 200,
    gamma: 100,
};

/// A point in the robot frame, mm (x forward, y left).
pub type PointMm = (i32, i32);

/// What the DWA decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DwaResult {
    /// The best admissible command.
    Command {
        /// Linear velocity, mm/s.
        v_mm_s: i32,
        /// Angular velocity, mrad/s.
        w_mrad_s: i32,
        /// Its score, per-mille of the best possible.
        score: i32,
        /// Its clearance, mm (capped).
        clearance_mm: i32,
    },
    /// Every sample collides or cannot stop in time.
    NoAdmissible,
}

/// One evaluated sample (for tests and the float reference).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sample {
    /// Linear velocity, mm/s.
    pub v_mm_s: i32,
    /// Angular velocity, mrad/s.
    pub w_mrad_s: i32,
    /// Admissible.
    pub ok: bool,
    /// Heading term, mrad (0..π).
    pub heading_mrad: i32,
    /// Clearance term, mm (capped).
    pub clearance_mm: i32,
}

/// The sampled velocities of the dynamic window around the current ones.
pub fn window(p: &DwaParams, v_mm_s: i32, w_mrad_s: i32) -> ([i32; V_SAMPLES], [i32; W_SAMPLES]) {
    let dv = p.acc_mm_s2 * p.dt_ms / 1000;
    let dw = p.w_acc_mrad_s2 * p.dt_ms / 1000;
    let (v0, v1) = (
        (v_mm_s - dv).max(p.v_min_mm_s),
        (v_mm_s + dv).min(p.v_max_mm_s),
    );
    let (w0, w1) = (
        (w_mrad_s - dw).max(-p.w_max_mrad_s),
        (w_mrad_s + dw).min(p.w_max_mrad_s),
    );
    let (v0, v1) = if v0 > v1 { (v1, v1) } else { (v0, v1) };
    let (w0, w1) = if w0 > w1 { (w1, w1) } else { (w0, w1) };
    let vs = core::array::from_fn(|i| v0 + (v1 - v0) * i as i32 / (V_SAMPLES as i32 - 1));
    let ws = core::array::from_fn(|i| w0 + (w1 - w0) * i as i32 / (W_SAMPLES as i32 - 1));
    (vs, ws)
}

/// Rolls out (v, ω) and measures it: (admissible, heading term, clearance).
/// At most [`MAX_OBSTACLES`] points are considered (the rest are ignored,
/// as in [`plan`]).
///
/// Distances are in µm with 32×32→64 multiplies and no division in the
/// inner loop (a 64-bit division is a library call on the Cortex-M4). For
/// constant (v, ω) each step turns by dθ: the midpoint direction is rotated
/// by a fixed (cos dθ, sin dθ) instead of a CORDIC per step. Va: the robot
/// must be able to brake to a stop before the first contact; a disc turning
/// on the spot sweeps nothing new, so v = 0 is always admissible.
pub fn evaluate(
    p: &DwaParams,
    v_mm_s: i32,
    w_mrad_s: i32,
    goal: PointMm,
    obstacles: &[PointMm],
) -> Sample {
    let (obs_um, n) = to_um(obstacles);
    evaluate_um(p, v_mm_s, w_mrad_s, goal, obs_um.get(..n).unwrap_or(&[]))
}

/// The first [`MAX_OBSTACLES`] points in µm, clamped to ±2 km (so that
/// they fit in i32), and how many there are.
fn to_um(obstacles: &[PointMm]) -> ([(i32, i32); MAX_OBSTACLES], usize) {
    let mut obs_um = [(0i32, 0i32); MAX_OBSTACLES];
    let mut n = 0;
    for (o, &(ox, oy)) in obs_um.iter_mut().zip(obstacles) {
        *o = (
            ox.clamp(-2_000_000, 2_000_000) * 1000,
            oy.clamp(-2_000_000, 2_000_000) * 1000,
        );
        n += 1;
    }
    (obs_um, n)
}

/// [`evaluate`] on obstacles already in µm (clamped to ±2 km), so that a
/// cycle converts them once, not once per sample and step.
fn evaluate_um(
    p: &DwaParams,
    v_mm_s: i32,
    w_mrad_s: i32,
    goal: PointMm,
    obs_um: &[(i32, i32)],
) -> Sample {
    let steps = (p.horizon_ms / p.step_ms.max(1)).max(1);
    let (mut x_um, mut y_um, mut th_urad) = (0i64, 0i64, 0i64);
    let r_um = p.radius_mm as i64 * 1000;
    let r2 = r_um * r_um;
    let mut min_d2 = i64::MAX;
    let step_um = v_mm_s as i64 * p.step_ms as i64; // mm/s · ms = µm
    let dth = w_mrad_s as i64 * p.step_ms as i64; // mrad/s · ms = µrad
    let mut travelled_um = 0i64;
    let mut hit_at_um: Option<i64> = None; // first contact along the arc, µm
    let (mut s, mut c) = sin_cos_q30(dth / 2);
    let (rs, rc) = sin_cos_q30(dth);
    for _ in 0..steps {
        x_um += (step_um * c) >> 30;
        y_um += (step_um * s) >> 30;
        th_urad += dth;
        (c, s) = ((c * rc - s * rs) >> 30, (s * rc + c * rs) >> 30);
        travelled_um += step_um.abs();
        // The rollout stays within ±horizon·v_max of the start, so these
        // fit in i32 µm for any obstacle within ±2 km.
        let (xi, yi) = (
            x_um.clamp(-(1 << 30), 1 << 30) as i32,
            y_um.clamp(-(1 << 30), 1 << 30) as i32,
        );
        let step_min = nearest_d2(obs_um, xi, yi);
        min_d2 = min_d2.min(step_min);
        // Touching at this step is the step's nearest point within r.
        if step_min <= r2 && hit_at_um.is_none() {
            hit_at_um = Some(travelled_um);
        }
    }
    // Clearance beyond the radius, mm (capped).
    let clearance = if min_d2 == i64::MAX {
        p.clearance_cap_mm as i64
    } else {
        (crate::math::cost::isqrt_u64(min_d2.max(0) as u64) as i64 / 1000 - p.radius_mm as i64)
            .max(0)
            .min(p.clearance_cap_mm as i64)
    };
    // Va (see above).
    let ok = match hit_at_um {
        None => true,
        Some(_) if v_mm_s == 0 => true,
        Some(h) => {
            let dist_mm = ((h - step_um.abs()) / 1000).max(0); // before the touching step
            let v = v_mm_s as i64;
            let w = w_mrad_s as i64;
            let ang_mrad = dist_mm * 1000 / p.radius_mm.max(1) as i64;
            v * v <= 2 * dist_mm * p.acc_mm_s2 as i64
                && w * w <= 2 * ang_mrad * p.w_acc_mrad_s2 as i64
        }
    };
    // Heading: π minus the angle between the final heading and the goal.
    let gx = goal.0 as i64 * 1000 - x_um;
    let gy = goal.1 as i64 * 1000 - y_um;
    let to_goal = atan2_urad(gy, gx);
    let mut err = (to_goal - th_urad).rem_euclid(6_283_185);
    if err > 3_141_593 {
        err = 6_283_185 - err;
    }
    Sample {
        v_mm_s,
        w_mrad_s,
        ok,
        heading_mrad: ((3_141_593 - err) / 1000) as i32,
        clearance_mm: clearance as i32,
    }
}

/// The smallest squared distance (µm²) from (x, y) µm to the obstacles;
/// `i64::MAX` for none. The hot loop of a cycle (samples × steps ×
/// points): a saturating subtract and a multiply-accumulate per axis.
#[inline]
fn nearest_d2(obs_um: &[(i32, i32)], x_um: i32, y_um: i32) -> i64 {
    let mut best = i64::MAX;
    for &(ox, oy) in obs_um {
        let dx = ox.saturating_sub(x_um) as i64;
        let dy = oy.saturating_sub(y_um) as i64;
        best = best.min(dx * dx + dy * dy);
    }
    best
}

/// One DWA cycle from the current velocities toward `goal` (robot frame).
pub fn plan(
    p: &DwaParams,
    v_mm_s: i32,
    w_mrad_s: i32,
    goal: PointMm,
    obstacles: &[PointMm],
) -> DwaResult {
    let (vs, ws) = window(p, v_mm_s, w_mrad_s);
    let mut samples = [Sample::default(); V_SAMPLES * W_SAMPLES];
    let (mut h_max, mut c_max, mut v_max) = (0i64, 0i64, 0i64);
    let (obs_um, n) = to_um(obstacles);
    let obs_um = obs_um.get(..n).unwrap_or(&[]);
    for (k, slot) in samples.iter_mut().enumerate() {
        let (v, w) = (
            vs.get(k / W_SAMPLES).copied().unwrap_or(0),
            ws.get(k % W_SAMPLES).copied().unwrap_or(0),
        );
        *slot = evaluate_um(p, v, w, goal, obs_um);
        if slot.ok {
            h_max = h_max.max(slot.heading_mrad as i64);
            c_max = c_max.max(slot.clearance_mm as i64);
            v_max = v_max.max(slot.v_mm_s.abs() as i64);
        }
    }
    let norm = |x: i64, m: i64| if m > 0 { x * 1000 / m } else { 0 };
    let mut best: Option<(i64, Sample)> = None;
    for s in samples.iter().filter(|s| s.ok) {
        let score = p.alpha as i64 * norm(s.heading_mrad as i64, h_max)
            + p.beta as i64 * norm(s.clearance_mm as i64, c_max)
            + p.gamma as i64 * norm(s.v_mm_s.abs() as i64, v_max);
        if best.is_none_or(|(b, _)| score > b) {
            best = Some((score, *s));
        }
    }
    match best {
        Some((score, s)) => DwaResult::Command {
            v_mm_s: s.v_mm_s,
            w_mrad_s: s.w_mrad_s,
            score: (score / 1000) as i32,
            clearance_mm: s.clearance_mm,
        },
        None => DwaResult::NoAdmissible,
    }
}

/// Keeps the `out.len()` obstacle points nearest to the robot from
/// `points` (robot frame, mm), nearest first; returns how many.
pub fn nearest_obstacles(points: &[PointMm], out: &mut [PointMm]) -> usize {
    crate::math::select::smallest_k(points, out, |p| {
        p.0 as i64 * p.0 as i64 + p.1 as i64 * p.1 as i64
    })
}

/// A recorded situation (robot frame): driving at 0.3 m/s toward a goal
/// 3 m ahead and 0.5 m left, a person-sized cluster of returns 0.9 m ahead
/// and a wall 0.6 m to the right. Shared by the host tests and the emulated
/// run, which must reach the same command.
pub const RECORDED_OBSTACLES: [PointMm; 24] = [
    (900, -100),
    (900, -50),
    (900, 0),
    (900, 50),
    (900, 100),
    (950, -120),
    (950, 120),
    (1000, 0),
    (200, -600),
    (400, -600),
    (600, -600),
    (800, -600),
    (1000, -600),
    (1200, -600),
    (1400, -600),
    (1600, -600),
    (0, -600),
    (-200, -600),
    (1800, -600),
    (2000, -600),
    (2200, -600),
    (2400, -600),
    (2600, -600),
    (2800, -600),
];
/// The recorded situation's goal, robot frame, mm.
pub const RECORDED_GOAL: PointMm = (3000, 500);
/// The recorded situation's current velocities (mm/s, mrad/s).
pub const RECORDED_VELOCITY: (i32, i32) = (300, 0);
/// The command the recorded situation gives (v mm/s, ω mrad/s).
pub const RECORDED_COMMAND: (i32, i32) = (250, 80);

/// The recorded situation at full capacity ([`MAX_OBSTACLES`] points, as
/// many as the mission offers): [`RECORDED_OBSTACLES`] and a second wall
/// 0.9 m to the left, a point every 100 mm from 1 m behind. The emulated
/// run measures the cycle's worst case on it.
pub fn recorded_full() -> [PointMm; MAX_OBSTACLES] {
    core::array::from_fn(|i| {
        RECORDED_OBSTACLES.get(i).copied().unwrap_or_else(|| {
            let k = i.saturating_sub(RECORDED_OBSTACLES.len()) as i32;
            (-1000 + 100 * k, 900)
        })
    })
}
/// The command [`recorded_full`] gives (v mm/s, ω mrad/s).
pub const RECORDED_FULL_COMMAND: (i32, i32) = (250, 80);
