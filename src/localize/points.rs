//! The scan as the matcher sees it: every `k`-th return of one revolution,
//! de-skewed (each frame placed by the odometry pose stamped on it, then
//! expressed in the robot's frame at the revolution's last frame), as
//! Hector SLAM and Cartographer do before matching.

use crate::math::angle::sin_cos_q30;
use crate::math::cost::{dist_mm, isqrt_u64};
use crate::robot::beam::{beams, Beam, LidarMount};
use crate::robot::lidar::scan::Scan;
use crate::robot::odometry::Pose;

use super::trail::Trail;
use super::PoseU;

/// Points kept per revolution (an LD06 revolution has about 450).
pub const MATCH_POINTS: usize = 224;

/// A scan point in the robot's frame, mm (x forward, y left). 16 bits
/// hold ± 32.7 m, beyond any lidar range the robot takes ([`LidarMount`]'s
/// is 12 m), and halve the points' RAM (896 bytes less than `i32`
/// pairs on the F411, where the stack has the least room).
pub type Pt = (i16, i16);

/// A point in `i16` mm, if it fits.
fn narrow(x: i64, y: i64) -> Option<Pt> {
    Some((i16::try_from(x).ok()?, i16::try_from(y).ok()?))
}

/// De-skewed scan points in the robot's frame at [`ScanPoints::reference`].
pub struct ScanPoints {
    pts: [Pt; MATCH_POINTS],
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
    pub fn as_slice(&self) -> &[Pt] {
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
        let fit = pts.iter().step_by(k);
        let fit = fit.filter_map(|&(x, y)| narrow(x.into(), y.into()));
        for (slot, p) in self.pts.iter_mut().zip(fit) {
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
            beams(
                pose,
                mount,
                frame,
                0,
                |&Beam {
                     end: (hx, hy), hit, ..
                 }| {
                    i += 1;
                    if !hit || !i.is_multiple_of(k) {
                        return;
                    }
                    let (dx, dy) = ((hx - r.x_mm) as i64, (hy - r.y_mm) as i64);
                    let px = (dx * c + dy * s) >> 30;
                    let py = (dy * c - dx * s) >> 30;
                    if let (Some(slot), Some(p)) = (self.pts.get_mut(self.len), narrow(px, py)) {
                        *slot = p;
                        self.len += 1;
                    }
                },
            );
        }
    }
}

/// Widest run of returns (mm, first to last) taken for a small object
/// standing free in front of what is behind it: a person's body or legs
/// (the twin's people are 300 mm discs), a chair or table leg.
pub const FOREGROUND_WIDTH_MM: i64 = 600;
/// How much nearer (mm) than both its neighbours a run must be to count
/// as standing in front of them.
pub const FOREGROUND_JUMP_MM: i64 = 150;
/// Adaptive breakpoint detection (Borges and Aldon, J. Intell. Robot.
/// Syst. 2004): neighbouring returns `a`, `b` belong to one surface unless
/// they are further apart than a wall seen at this grazing angle would put
/// them, r·sin Δφ / sin(λ − Δφ), plus the range noise. λ = 10° (sin, cos
/// in ‰): a wall is one run until it is seen within 10° of edge-on, so the
/// widening gaps along a wall seen obliquely never cut a piece off it.
const GRAZING_SIN_COS_PERMILLE: (i64, i64) = (174, 985);
/// Range noise allowed on top of the breakpoint distance, mm (3σ of the
/// twin's realistic lidar and of the LD06's datasheet accuracy).
const BREAK_NOISE_MM: i64 = 40;
/// Widest angle (sin, ‰: 5°) between two returns still taken as
/// neighbours. The returns kept for the match are about 2.4° apart (every
/// third of the LD06's 450 a revolution), so a wider angle means returns
/// were lost between them (no echo), and nothing is known of what is there.
const NEIGHBOUR_SIN_PERMILLE: i64 = 87;

impl ScanPoints {
    /// Drops every run of returns that stands free in front of both its
    /// neighbours (range steps of more than [`FOREGROUND_JUMP_MM`] toward
    /// the lidar on both sides) and is at most [`FOREGROUND_WIDTH_MM`]
    /// wide; returns how many points were dropped.
    ///
    /// **Why** (unknown mode, issue 10 §2 "unmapped points must not
    /// pull"): there the map is built from the scans, so a person who
    /// stands still for half a second is mapped like a wall, and when they
    /// move, their returns land beside their own mapped cells and pull the
    /// pose after them. A person walking beside the robot along a corridor
    /// (whose walls fix only one axis) dragged the estimate 700 mm in the
    /// twin (the S6 home), and the map was then rebuilt in the wrong frame.
    /// This is the segment-based dynamic filtering of 2-D lidar odometry
    /// (leg detectors split a scan at range jumps the same way, Arras et
    /// al., ICRA 2007): walls, seen from inside a room, are long and
    /// continuous; what stands free in front of them is small.
    ///
    /// What is kept: walls, however short a stretch is seen between two
    /// people (it lies behind its neighbours, not in front); door jambs
    /// and wall ends (the wall continues on one side); any run next to a
    /// gap of lost returns; a wall's end seen within 10° of edge-on, where
    /// the wall itself breaks into runs (its neighbour and the one beyond
    /// lie on the run's line). What is lost with the people: free-standing
    /// furniture narrower than [`FOREGROUND_WIDTH_MM`]. What is missed: a
    /// person standing before a wall that is itself seen edge-on looks
    /// like that wall's end, and is kept. Points are dropped from the match
    /// only: the map still gets every return, since the planner must avoid
    /// people.
    pub fn drop_foreground(&mut self) -> u32 {
        let n = self.len;
        let pts = self.pts.get(..n).unwrap_or(&[]);
        let at = |i: usize| {
            let (x, y) = pts.get(i % n.max(1)).copied().unwrap_or((0, 0));
            (i32::from(x), i32::from(y))
        };
        let Some(start) = (0..n).find(|&i| splits(at(i + n - 1), at(i))) else {
            return 0;
        };
        let mut dropped = [0u32; MATCH_POINTS.div_ceil(32)];
        let (mut s, mut seen) = (start, 0usize);
        while seen < n {
            let mut len = 1;
            while len < n && !splits(at(s + len - 1), at(s + len)) {
                len += 1;
            }
            let (first, last) = (at(s), at(s + len - 1));
            if len < n
                && in_front(first, at(s + n - 1), at(s + 2 * n - 2))
                && in_front(last, at(s + len), at(s + len + 1))
                && dist_mm(first, last) <= FOREGROUND_WIDTH_MM
            {
                for j in (s..s + len).map(|i| i % n) {
                    if let Some(w) = dropped.get_mut(j / 32) {
                        *w |= 1 << (j % 32);
                    }
                }
            }
            seen += len;
            s = (s + len) % n;
        }
        self.compact(&dropped)
    }

    /// Drops every point that lands on floor the robot's body swept a
    /// moment ago ([`Trail::swept`], placed by [`Self::reference`]):
    /// something that moved in since, a person following the robot
    /// ([`super::trail`]). Returns how many points were dropped.
    pub fn drop_on(&mut self, trail: &Trail) -> u32 {
        let Some((x0, y0, x1, y1)) = trail.bounds() else {
            return 0;
        };
        let r = self.reference;
        let sc = sin_cos_q30(r.theta_urad);
        let mut dropped = [0u32; MATCH_POINTS.div_ceil(32)];
        for (i, &p) in self.as_slice().iter().enumerate() {
            let (x, y) = place(&r, sc, p);
            if (x0..=x1).contains(&x) && (y0..=y1).contains(&y) && trail.swept((x, y)) {
                if let Some(w) = dropped.get_mut(i / 32) {
                    *w |= 1 << (i % 32);
                }
            }
        }
        self.compact(&dropped)
    }

    /// Keeps the points whose bit in `dropped` is clear, in order.
    fn compact(&mut self, dropped: &[u32]) -> u32 {
        let n = self.len;
        let mut kept = 0;
        for i in 0..n {
            let gone = dropped
                .get(i / 32)
                .is_some_and(|w| w & (1 << (i % 32)) != 0);
            if let (false, Some(&p)) = (gone, self.pts.get(i)) {
                if let Some(slot) = self.pts.get_mut(kept) {
                    *slot = p;
                }
                kept += 1;
            }
        }
        self.len = kept;
        (n - kept) as u32
    }
}

/// Range of a robot-frame point, mm.
fn range(p: (i32, i32)) -> i64 {
    let (x, y) = (p.0.unsigned_abs() as u64, p.1.unsigned_abs() as u64);
    isqrt_u64(x * x + y * y) as i64
}

/// True when `a` and `b` are neighbours in angle (no returns lost between
/// them, [`NEIGHBOUR_SIN_PERMILLE`]).
fn adjacent(a: (i32, i32), b: (i32, i32)) -> bool {
    let (ax, ay, bx, by) = (a.0 as i128, a.1 as i128, b.0 as i128, b.1 as i128);
    let cross = (ax * by - ay * bx).abs();
    let scale = NEIGHBOUR_SIN_PERMILLE as i128 * range(a) as i128 * range(b) as i128;
    ax * bx + ay * by > 0 && cross * 1000 <= scale
}

/// True when a run ends between neighbouring returns `a` and `b`: returns
/// lost between them, or further apart than one surface would put them
/// ([`GRAZING_SIN_COS_PERMILLE`]).
fn splits(a: (i32, i32), b: (i32, i32)) -> bool {
    if !adjacent(a, b) {
        return true;
    }
    let (ax, ay, bx, by) = (a.0 as i128, a.1 as i128, b.0 as i128, b.1 as i128);
    let cross = (ax * by - ay * bx).abs();
    let (sin_l, cos_l) = GRAZING_SIN_COS_PERMILLE;
    // sin(λ − Δφ)·rₐr_b·1000; positive, since `adjacent` keeps Δφ ≤ 5°.
    let den = sin_l as i128 * (ax * bx + ay * by) - cos_l as i128 * cross;
    let gap = dist_mm(a, b) as i128 - BREAK_NOISE_MM as i128;
    den <= 0 || gap * den > 1000 * range(a) as i128 * cross
}

/// True when `end` (a run's end) stands in front of `next`, its neighbour
/// across the split, and `beyond` is the neighbour's own next return:
/// adjacent in angle, nearer by a range step, and not one surface seen
/// edge-on (there `end`, `next` and `beyond` lie on one line; behind a
/// person the wall runs across the beams instead).
fn in_front(end: (i32, i32), next: (i32, i32), beyond: (i32, i32)) -> bool {
    adjacent(next, end)
        && range(next) - range(end) > FOREGROUND_JUMP_MM
        && adjacent(next, beyond)
        && !same_line(end, next, beyond)
}

/// True when the steps `a`→`b` and `b`→`c` run the same way (within
/// 20°: sin 342 ‰).
fn same_line(a: (i32, i32), b: (i32, i32), c: (i32, i32)) -> bool {
    let (ux, uy) = (b.0 as i128 - a.0 as i128, b.1 as i128 - a.1 as i128);
    let (vx, vy) = (c.0 as i128 - b.0 as i128, c.1 as i128 - b.1 as i128);
    let cross = (ux * vy - uy * vx).abs();
    ux * vx + uy * vy > 0 && cross * 1000 <= 342 * dist_mm(a, b) as i128 * dist_mm(b, c) as i128
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
pub fn place(pose: &PoseU, sc: (i64, i64), p: Pt) -> (i32, i32) {
    let (s, c) = sc;
    let (px, py) = (p.0 as i64, p.1 as i64);
    let x = pose.x_mm as i64 + ((px * c - py * s) >> 30);
    let y = pose.y_mm as i64 + ((px * s + py * c) >> 30);
    let clamp = |v: i64| v.clamp(-(1 << 30), 1 << 30) as i32;
    (clamp(x), clamp(y))
}
