//! Lidar beams in the world: where the lidar sits ([`LidarMount`]), each
//! return of a frame as a segment in world millimetres ([`beams`]), and
//! the exact walk over the cells a segment passes through ([`walk`]),
//! which the evidence map clears.

use crate::math::angle::sin_cos_q30;
use crate::robot::lidar::LidarFrame;
use crate::robot::odometry::Pose;

/// Where the lidar sits on the robot and how its angles run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LidarMount {
    /// Forward offset from the robot's centre, mm.
    pub offset_x_mm: i32,
    /// Leftward offset, mm.
    pub offset_y_mm: i32,
    /// Bearing of the robot's forward axis in the lidar's own angles, mrad.
    pub zero_mrad: i32,
    /// True when the lidar's angles grow clockwise (LD06/LD19 do).
    pub clockwise: bool,
    /// Shortest range used, mm.
    pub min_range_mm: u16,
    /// Longest range used, mm.
    pub max_range_mm: u16,
}

impl LidarMount {
    /// An LD06/LD19 at the robot's centre, its zero bearing forward, using
    /// ranges of 20 mm to 12 m (the datasheet's span); `clockwise` as its
    /// angles grow (the real sensor's, true; a mirrored test stream's,
    /// false).
    pub const fn ld06_centred(clockwise: bool) -> Self {
        Self {
            offset_x_mm: 0,
            offset_y_mm: 0,
            zero_mrad: 0,
            clockwise,
            min_range_mm: 20,
            max_range_mm: 12_000,
        }
    }
}

/// One lidar beam in world mm: from the lidar at `origin` to the return
/// at `end`; `past` lies the caller's margin further along it (inside the
/// obstacle). With no return within range, `end` and `past` are the
/// longest range and `hit` is false.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Beam {
    /// The lidar's position.
    pub origin: (i32, i32),
    /// The return (or the longest range).
    pub end: (i32, i32),
    /// `past_hit_mm` beyond the return (or the longest range).
    pub past: (i32, i32),
    /// True for a return within range.
    pub hit: bool,
}

/// Every usable beam of a frame taken at `pose`, in world mm: calls `f`
/// with each ([`Beam`]; a return's `past` lies `past_hit_mm` beyond it).
/// Shared by the evidence map and the executive's obstacle points.
pub fn beams(
    pose: &Pose,
    mount: &LidarMount,
    frame: &LidarFrame,
    past_hit_mm: i64,
    mut f: impl FnMut(&Beam),
) {
    let th = pose.theta_mrad as i64 * 1000;
    let (s, c) = sin_cos_q30(th);
    let ox =
        pose.x_mm as i64 + ((mount.offset_x_mm as i64 * c - mount.offset_y_mm as i64 * s) >> 30);
    let oy =
        pose.y_mm as i64 + ((mount.offset_x_mm as i64 * s + mount.offset_y_mm as i64 * c) >> 30);
    let clamp = |v: i64| v.clamp(-(1 << 30), 1 << 30) as i32;
    for p in frame.points() {
        if p.dist_mm == 0 || p.dist_mm < mount.min_range_mm {
            continue;
        }
        let (range, hit) = if p.dist_mm > mount.max_range_mm {
            (mount.max_range_mm as i64, false)
        } else {
            (p.dist_mm as i64, true)
        };
        // Bearing in the lidar's angles → robot frame → world.
        let b_urad = p.angle_cdeg as i64 * 174_533 / 1000 - mount.zero_mrad as i64 * 1000;
        let rel = if mount.clockwise { -b_urad } else { b_urad };
        let (bs, bc) = sin_cos_q30(th + rel);
        let at = |reach: i64| {
            (
                clamp(ox + ((reach * bc) >> 30)),
                clamp(oy + ((reach * bs) >> 30)),
            )
        };
        let past = range + if hit { past_hit_mm } else { 0 };
        f(&Beam {
            origin: (clamp(ox), clamp(oy)),
            end: at(range),
            past: at(past),
            hit,
        });
    }
}

/// Calls `f(column, row)` (counted from the bottom-left, cells of `res_mm`)
/// for every cell the segment a → b (world mm) truly passes through,
/// in order, before b's own cell. Exact, in integer cross-multiplication
/// (Amanatides & Woo 1987, "A fast voxel traversal algorithm"): a
/// Bresenham line between the cells' centres strays up to half a cell
/// off the beam, and a beam grazing a wall, ending in the wall's row,
/// ran its last cells along that row and cleared the wall's face (on the
/// real homes in unknown mode, one wall-face cell in eight read free).
/// Four-connected: through a corner exactly, the step along a positive
/// axis comes first (x when both are), since a point on a cell boundary
/// belongs to the cell above or to the right of it: a segment ending
/// exactly on a corner while moving left and up so never enters the
/// column left of its end (CI drew (2651, 1) -> (2650, 950), which
/// stepped into column 52 and cleared a cell the beam only touches).
/// Bounded: each step moves one cell closer to b's.
pub fn walk(a: (i32, i32), b: (i32, i32), res_mm: u32, mut f: impl FnMut(i64, i64)) {
    // Moving left and up, the walk runs on the mirrored axes (x and y
    // swapped), where the tie goes to the original y: the same loop,
    // so no extra work per cell in the map update's inner loop.
    if b.0 < a.0 && b.1 > a.1 {
        walk_x_first((a.1, a.0), (b.1, b.0), res_mm, |y, x| f(x, y));
    } else {
        walk_x_first(a, b, res_mm, f);
    }
}

/// [`walk`] with ties always to x.
fn walk_x_first(a: (i32, i32), b: (i32, i32), res_mm: u32, mut f: impl FnMut(i64, i64)) {
    let r = res_mm.max(1) as i64;
    let (x0, y0) = (a.0 as i64, a.1 as i64);
    let (dx, dy) = (b.0 as i64 - x0, b.1 as i64 - y0);
    let (mut ix, mut iy) = (x0.div_euclid(r), y0.div_euclid(r));
    let (ex, ey) = ((b.0 as i64).div_euclid(r), (b.1 as i64).div_euclid(r));
    let (sx, sy) = (dx.signum(), dy.signum());
    // The segment reaches the next x boundary before the next y one when
    // |bx - x0| / |dx| <= |by - y0| / |dy|; cross-multiplied, the two
    // sides are `px` and `py`, and each step adds a whole cell's worth
    // to one (r |dy| or r |dx|): additions only in the loop. Below 2^63
    // for coordinates within ±2^30 mm; an axis the segment does not move
    // along is never stepped.
    let (adx, ady) = (dx.abs(), dy.abs());
    let first = |i: i64, s: i64, o: i64| (if s > 0 { (i + 1) * r } else { i * r } - o).abs();
    let mut px = if sx == 0 {
        i64::MAX
    } else {
        first(ix, sx, x0) * ady
    };
    let mut py = if sy == 0 {
        i64::MAX
    } else {
        first(iy, sy, y0) * adx
    };
    for _ in 0..=((ex - ix).abs() + (ey - iy).abs()) {
        if (ix, iy) == (ex, ey) {
            break;
        }
        f(ix, iy);
        if px <= py {
            ix += sx;
            px = px.saturating_add(r * ady);
        } else {
            iy += sy;
            py = py.saturating_add(r * adx);
        }
    }
}
