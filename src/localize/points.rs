//! The scan as the matcher sees it: every `k`-th return of one revolution,
//! de-skewed (each frame placed by the odometry pose stamped on it, then
//! expressed in the robot's frame at the revolution's last frame), as
//! Hector SLAM and Cartographer do before matching.

use crate::math::angle::sin_cos_q30;
use crate::robot::lidar::scan::Scan;
use crate::robot::lidar_map::{beams, LidarMount};
use crate::robot::odometry::Pose;

use super::PoseU;

/// Points kept per revolution (an LD06 revolution has about 450).
pub const MATCH_POINTS: usize = 224;

/// De-skewed scan points in the robot's frame at [`ScanPoints::reference`].
pub struct ScanPoints {
    pts: [(i32, i32); MATCH_POINTS],
    len: usize,
    reference: PoseU,
}

impl Default for ScanPoints {
    fn default() -> Self {
        Self::new()
    }
}

impl ScanPoints {
    /// No points.
    pub const fn new() -> Self {
        Self {
            pts: [(0, 0); MATCH_POINTS],
            len: 0,
            reference: PoseU {
                x_mm: 0,
                y_mm: 0,
                theta_urad: 0,
            },
        }
    }

    /// The points, robot frame mm (x forward, y left).
    pub fn as_slice(&self) -> &[(i32, i32)] {
        self.pts.get(..self.len).unwrap_or(&[])
    }

    /// The odometry pose the points are expressed at (the last frame's).
    pub fn reference(&self) -> PoseU {
        self.reference
    }

    /// Replaces the points (tests and recorded scans): every `k`-th, so
    /// that at most [`MATCH_POINTS`] remain.
    pub fn set(&mut self, reference: PoseU, pts: &[(i32, i32)]) {
        self.len = 0;
        self.reference = reference;
        let k = pts.len().div_ceil(MATCH_POINTS).max(1);
        for (slot, &p) in self.pts.iter_mut().zip(pts.iter().step_by(k)) {
            *slot = p;
            self.len += 1;
        }
    }

    /// Loads a revolution: returns at their measured range (on the wall's
    /// face, where the fine level wants them), every `k`-th so that at
    /// most [`MATCH_POINTS`] remain.
    pub fn load<const F: usize>(&mut self, scan: &Scan<F>, mount: &LidarMount) {
        self.len = 0;
        let Some((last, _)) = scan.frames().last() else {
            return;
        };
        let r = pose_u(last);
        self.reference = r;
        let (s, c) = sin_cos_q30(r.theta_urad);
        let total = scan.point_count().max(1);
        let k = total.div_ceil(MATCH_POINTS).max(1);
        let mut i = 0usize;
        for (pose, frame) in scan.frames() {
            beams(pose, mount, frame, 0, |_, _, hx, hy, hit| {
                i += 1;
                if !hit || !i.is_multiple_of(k) {
                    return;
                }
                let (dx, dy) = ((hx - r.x_mm) as i64, (hy - r.y_mm) as i64);
                let px = ((dx * c + dy * s) >> 30) as i32;
                let py = ((dy * c - dx * s) >> 30) as i32;
                if let Some(slot) = self.pts.get_mut(self.len) {
                    *slot = (px, py);
                    self.len += 1;
                }
            });
        }
    }
}

/// An odometry pose in the matcher's units.
pub fn pose_u(p: &Pose) -> PoseU {
    PoseU {
        x_mm: p.x_mm,
        y_mm: p.y_mm,
        theta_urad: p.theta_mrad as i64 * 1000,
    }
}

/// Robot-frame point `p` placed in the world by `pose`, with the pose's
/// (sin, cos) in Q30.
#[inline]
pub fn place(pose: &PoseU, sc: (i64, i64), p: (i32, i32)) -> (i32, i32) {
    let (s, c) = sc;
    let (px, py) = (p.0 as i64, p.1 as i64);
    let x = pose.x_mm as i64 + ((px * c - py * s) >> 30);
    let y = pose.y_mm as i64 + ((px * s + py * c) >> 30);
    let clamp = |v: i64| v.clamp(-(1 << 30), 1 << 30) as i32;
    (clamp(x), clamp(y))
}
