//! Gauss–Newton refinement of a pose against one map level (Hector SLAM,
//! Kohlbrecher et al. 2011, §IV-B, eq. 7–13): minimise
//! Σ (T − M(Sᵢ(ξ)))² over ξ = (x, y, θ), where M is the interpolated wall
//! layer ([`super::field`]), T its target (½ on the fine level: the
//! wall's face; 1 on coarse ones) and Sᵢ places point i.
//!
//! Units: the translation unknowns are level cells, the heading unknown
//! radians; the Jacobian is Q8 per unit, so the normal matrix H = ΣJᵀJ is
//! Q16 and fits i64 for any map up to 2^20 mm with [`super::MATCH_POINTS`]
//! points. The 3 × 3 solve is Cramer's rule in i128 after a common shift
//! that keeps every entry below 2^30 (the solution does not change when H
//! and b are scaled together). A mild Levenberg damping (H_ii/16, and on
//! the translation 1/256 of its larger diagonal) keeps a near-singular H
//! (a corridor) from taking a wild step, and each step is capped at one
//! level cell and 50 mrad.

use super::field::Field;
use super::points::{place, Pt};
use super::PoseU;
use crate::math::angle::sin_cos_q30;

/// The normal equations of one iteration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Normal {
    /// H = ΣJᵀJ: xx, xy, xθ, yy, yθ, θθ (Q16; translation per level cell,
    /// heading per radian).
    pub h: [i64; 6],
    /// b = ΣJᵀ(T − M), Q16.
    pub b: [i64; 3],
    /// Points with a gradient (near a wall).
    pub near: u32,
    /// Points on a wall ([`super::field::Field::inlier`]).
    pub inliers: u32,
    /// H's translational block (xx, xy, yy) from the points at least
    /// [`FAR_MM`] from the lidar only; filled by [`normal_far`], zero from
    /// [`normal`].
    pub far: [i64; 3],
}

/// Range from which a point's information counts in [`Normal::far`], mm.
/// A person following the robot stands about 0.35 m centre to centre,
/// their near side 0.2 m from the lidar (the twin's 300 mm discs). 450 mm
/// was tried: in the office flat's 0.5 m door passage the side walls lie
/// within it, every match there became partial while the robot turned on
/// the spot, and the pose drifted 150 mm along the passage's width.
pub const FAR_MM: i64 = 300;

/// Builds the normal equations at `pose`.
pub fn normal<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    pose: &PoseU,
) -> Normal {
    accumulate::<EV, MW, false>(field, pts, pose)
}

/// [`normal`] with [`Normal::far`] filled in (a separate instance, so that
/// the matches that do not need it pay nothing for it).
pub fn normal_far<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    pose: &PoseU,
) -> Normal {
    accumulate::<EV, MW, true>(field, pts, pose)
}

/// The sums of [`normal`], and of [`Normal::far`] when `FAR`.
fn accumulate<const EV: usize, const MW: usize, const FAR: bool>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    pose: &PoseU,
) -> Normal {
    let sc = sin_cos_q30(pose.theta_urad);
    let cell = field.cell_mm().max(1) as i64;
    let mut n = Normal::default();
    for &p in pts {
        let (wx, wy) = place(pose, sc, p);
        let s = field.sample(wx, wy);
        let (rx, ry) = ((wx - pose.x_mm) as i64, (wy - pose.y_mm) as i64);
        if !facing(&s, rx, ry) {
            continue;
        }
        if field.inlier(&s) {
            n.inliers += 1;
        }
        n.near += 1;
        let (jx, jy) = (s.gx_q8 as i64, s.gy_q8 as i64);
        // ∂S/∂θ = (−(wy − y), wx − x), in level cells per radian.
        let jt = (jy * rx - jx * ry) / cell;
        let e = (field.target_q8() - s.m_q8) as i64;
        n.h[0] += jx * jx;
        n.h[1] += jx * jy;
        n.h[2] += jx * jt;
        n.h[3] += jy * jy;
        n.h[4] += jy * jt;
        n.h[5] += jt * jt;
        if FAR && rx * rx + ry * ry >= FAR_MM * FAR_MM {
            n.far[0] += jx * jx;
            n.far[1] += jx * jy;
            n.far[2] += jy * jy;
        }
        n.b[0] += jx * e;
        n.b[1] += jy * e;
        n.b[2] += jt * e;
    }
    n
}

/// True when the sample lies on a face turned toward the lidar: the wall
/// value rises along the beam (`rx`, `ry`: the beam's direction). A lidar
/// sees the near face of a wall, never the back of a thin one; without
/// this test a pose one wall-thickness off (100 mm behind 10 cm walls)
/// fits as well as the truth.
#[inline]
pub fn facing(s: &super::field::Sample, rx: i64, ry: i64) -> bool {
    s.gx_q8 as i64 * rx + s.gy_q8 as i64 * ry > 0
}

/// Solves the damped normal equations: (Δx mm, Δy mm, Δθ µrad), capped;
/// `None` when singular.
pub fn solve(n: &Normal, cell_mm: i32) -> Option<(i32, i32, i64)> {
    let mut h = n.h;
    // Levenberg damping: each diagonal by 1/16 of itself, and the
    // translation's also by 1/256 of the larger translational one, so an
    // axis nothing constrains (a corridor) takes no wild step.
    let floor = h[0].max(h[3]) / 256;
    for (i, extra) in [(0usize, floor), (3, floor), (5, 0)] {
        if let Some(v) = h.get_mut(i) {
            *v += *v / 16 + extra + 1;
        }
    }
    let big = h.iter().chain(n.b.iter()).map(|v| v.unsigned_abs()).max()?;
    let shift = (64 - big.leading_zeros()).saturating_sub(30);
    let [a, b, c, d, e, f] = h.map(|v| (v >> shift) as i128);
    let [p, q, r] = n.b.map(|v| (v >> shift) as i128);
    // Symmetric [[a b c] [b d e] [c e f]].
    let det = a * (d * f - e * e) - b * (b * f - e * c) + c * (b * e - d * c);
    if det <= 0 {
        return None;
    }
    let nx = p * (d * f - e * e) - b * (q * f - e * r) + c * (q * e - d * r);
    let ny = a * (q * f - r * e) - p * (b * f - e * c) + c * (b * r - q * c);
    let nt = a * (d * r - e * q) - b * (b * r - q * c) + p * (b * e - d * c);
    let cell = cell_mm as i128;
    // max/min, not clamp: a negative cell size must not assert.
    let dx = (nx * cell / det).max(-cell).min(cell) as i32;
    let dy = (ny * cell / det).max(-cell).min(cell) as i32;
    let dt = (nt * 1_000_000 / det).clamp(-50_000, 50_000) as i64;
    Some((dx, dy, dt))
}

/// Up to `iters` Gauss–Newton steps from `start` on one level; stops early
/// once a step moves less than 1 mm and 0.2 mrad. Returns the pose and the
/// normal equations at it.
pub fn refine<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    start: PoseU,
    iters: u32,
) -> (PoseU, Normal) {
    let mut pose = start;
    let mut n = normal(field, pts, &pose);
    for _ in 0..iters {
        let Some((dx, dy, dt)) = solve(&n, field.cell_mm()) else {
            break;
        };
        pose.x_mm = pose.x_mm.saturating_add(dx);
        pose.y_mm = pose.y_mm.saturating_add(dy);
        pose.theta_urad += dt;
        n = normal(field, pts, &pose);
        if dx.abs() <= 1 && dy.abs() <= 1 && dt.abs() < 200 {
            break;
        }
    }
    (pose, n)
}
