//! Assembles frames into one revolution, each frame stamped with the
//! odometry pose at its arrival, so every point can be placed in the world
//! even while the robot moves during the turn (per-frame de-skewing).

use super::LidarFrame;
use crate::math::angle::wrap_mrad;
use crate::robot::odometry::Pose;

/// One revolution: up to `F` frames, each with the pose it arrived at.
#[derive(Clone, Debug)]
pub struct Scan<const F: usize> {
    frames: [(Pose, LidarFrame); F],
    len: usize,
    /// Frames dropped because the scan was full.
    pub overflowed: u32,
}

impl<const F: usize> Default for Scan<F> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const F: usize> Scan<F> {
    /// An empty scan.
    pub const fn new() -> Self {
        Self {
            frames: [(
                Pose {
                    x_mm: 0,
                    y_mm: 0,
                    theta_mrad: 0,
                },
                LidarFrame {
                    speed_dps: 0,
                    start_cdeg: 0,
                    end_cdeg: 0,
                    timestamp_ms: 0,
                    count: 0,
                    points: [super::LidarPoint {
                        angle_cdeg: 0,
                        dist_mm: 0,
                        intensity: 0,
                    }; super::MAX_POINTS_PER_FRAME],
                },
            ); F],
            len: 0,
            overflowed: 0,
        }
    }

    /// The frames with their poses.
    pub fn frames(&self) -> &[(Pose, LidarFrame)] {
        self.frames.get(..self.len).unwrap_or(&[])
    }

    /// Number of points.
    pub fn point_count(&self) -> usize {
        self.frames().iter().map(|(_, f)| f.count as usize).sum()
    }

    /// Moves every frame's pose by a correction (Δx, Δy mm, Δθ mrad), so
    /// the revolution is mapped where the scan matcher placed it.
    pub fn shift(&mut self, dx_mm: i32, dy_mm: i32, dtheta_mrad: i32) {
        let n = self.len;
        for (pose, _) in self.frames.iter_mut().take(n) {
            pose.x_mm = pose.x_mm.saturating_add(dx_mm);
            pose.y_mm = pose.y_mm.saturating_add(dy_mm);
            pose.theta_mrad = pose.theta_mrad.saturating_add(dtheta_mrad);
        }
    }

    /// How far the robot moved during the revolution: the largest
    /// position (mm, Manhattan) and heading (mrad) change from the first
    /// frame.
    pub fn motion(&self) -> (i32, i32) {
        let Some((p0, _)) = self.frames().first() else {
            return (0, 0);
        };
        self.frames().iter().fold((0, 0), |(d, t), (p, _)| {
            let dd = (p.x_mm - p0.x_mm).abs() + (p.y_mm - p0.y_mm).abs();
            (
                d.max(dd),
                t.max(wrap_mrad(p.theta_mrad - p0.theta_mrad).abs()),
            )
        })
    }

    fn clear(&mut self) {
        self.len = 0;
        self.overflowed = 0;
    }
}

/// Collects frames until the bearing wraps past 0°, then hands over the
/// completed revolution. Overflow policy: frames beyond `F` in one
/// revolution are dropped and counted (the scan stays usable).
#[derive(Clone, Debug)]
pub struct ScanAssembler<const F: usize> {
    current: Scan<F>,
    last_start: Option<u16>,
    /// Completed revolutions.
    pub scans: u32,
}

impl<const F: usize> Default for ScanAssembler<F> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const F: usize> ScanAssembler<F> {
    /// An empty assembler.
    pub const fn new() -> Self {
        Self {
            current: Scan::new(),
            last_start: None,
            scans: 0,
        }
    }

    /// The revolution being assembled moved by (`dx`, `dy`) mm (the map
    /// scrolled under it).
    pub fn shift(&mut self, dx_mm: i32, dy_mm: i32) {
        self.current.shift(dx_mm, dy_mm, 0);
    }

    /// Adds a frame that arrived at `pose`. When it begins a new
    /// revolution, the finished one is copied into `out` and `true` is
    /// returned.
    pub fn push(&mut self, frame: &LidarFrame, pose: Pose, out: &mut Scan<F>) -> bool {
        let wrapped = self.last_start.is_some_and(|s| frame.start_cdeg < s);
        self.last_start = Some(frame.start_cdeg);
        let mut done = false;
        if wrapped && self.current.len > 0 {
            out.frames = self.current.frames;
            out.len = self.current.len;
            out.overflowed = self.current.overflowed;
            self.current.clear();
            self.scans += 1;
            done = true;
        }
        match self.current.frames.get_mut(self.current.len) {
            Some(slot) => {
                *slot = (pose, *frame);
                self.current.len += 1;
            }
            None => self.current.overflowed += 1,
        }
        done
    }
}
