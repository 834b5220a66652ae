//! Keeping the body off the walls it passes alongside. Ours, not from the
//! papers: a vacuum's side wall sensor, made from the map.
//!
//! The plans keep the body's rim 10 mm from mapped walls (the
//! configuration space's margin), and a straight move between two of its
//! positions may pass 5 mm from a cell's corner
//! ([`crate::mission::MissionConfig::sweep_mm`]). The follower's transients
//! are larger than that: a sub-path starts up to 10 mm off its line (the
//! last one ended within `arrive_mm`) and with the heading a turn in place
//! left. Measured on a real home (z10, known map, realistic noise, 1
//! person), its cross-track error exceeded 10 mm in 1 % of the driving
//! periods, up to 33 mm, nearly all in a sub-path's first 100 mm; the body
//! grazed a wall 4 times (the estimate agreed with the truth within 3 mm:
//! the follower, not the localisation).
//!
//! So the control loop steers away from a wall beside the body whose rim
//! comes within `keep_mm` of it, at a turn rate proportional to how far
//! inside: a lateral spring that only acts near walls. The walls are the
//! nearest blocking evidence cells (occupied, zone or off the map),
//! gathered by the planning step, which owns the map (the control tick
//! touches no big buffer, [`crate::mission`]), and measured every period
//! from the estimated pose to each cell's square: exact where a lidar
//! return is noisy (σ 10 mm). A wall ahead is the guard's; this acts only
//! on walls at least 27° off the heading.
//!
//! On the cleaning legs the mission uses it in known mode only
//! ([`crate::mission::MissionConfig::new`]): in unknown mode the walls are
//! the robot's own map, jagged where beams graze them, and steering off
//! them cost floor along the walls (a real home, seed 4: 96.35 → 91.47 %).
//! On the legs that clean nothing (transits, the way home) it acts in
//! both modes and from farther off (`keep_off_transit`): there the floor
//! beside the wall does not matter, and most of the last grazes were
//! there.

use super::cspace;
use super::geometry::RobotFrame;
use crate::math::cost::isqrt_u64;
use crate::robot::lidar_map::EvidenceMap;
use crate::robot::odometry::Pose;
use heapless::Vec;

/// Blocking cells kept for the control loop: the nearest this many.
pub const NEAR_CELLS: usize = 4;

/// Steps along each side of a cell in [`NearWalls::outline_points`].
pub const OUTLINE_STEPS: i32 = 10;

/// Tuning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct KeepOffParams {
    /// The rim's distance from a wall beside it below which the robot
    /// steers away, mm (0: off).
    pub keep_mm: i32,
    /// Turn rate per mm inside `keep_mm`, mrad/s.
    pub gain_mrad_s_per_mm: i32,
    /// Largest turn rate added, mrad/s.
    pub max_w_mrad_s: i32,
    /// Speed cap while the rim is more than half-way inside `keep_mm`,
    /// mm/s: slow enough that the turn away acts before the body closes
    /// the rest.
    pub slow_mm_s: i32,
}

/// The nearest blocking evidence cells to where the robot was at the last
/// planning step, as world squares (their south-west corners, mm), nearest
/// first.
#[derive(Clone, Debug, Default)]
pub struct NearWalls {
    corners: Vec<(i32, i32), NEAR_CELLS>,
    res_mm: i32,
}

impl NearWalls {
    /// No walls known.
    pub const fn new() -> Self {
        Self {
            corners: Vec::new(),
            res_mm: 0,
        }
    }

    /// The [`NEAR_CELLS`] blocking cells of `map` nearest to `here` (world
    /// mm) within `reach_mm`; unknown cells do not block. Overflow policy:
    /// farther cells are dropped. Work: (2·reach/res + 2)² cells.
    pub fn gather<const EV: usize>(map: &EvidenceMap<EV>, here: (i32, i32), reach_mm: i32) -> Self {
        let res = map.res_mm().max(1) as i64;
        let hmm = map.height() as i64 * res;
        let (px, py) = (here.0 as i64, hmm - here.1 as i64);
        let reach = reach_mm.max(0) as i64;
        let mut best: Vec<(i64, (i32, i32)), NEAR_CELLS> = Vec::new();
        for cy in (py - reach).div_euclid(res)..=(py + reach).div_euclid(res) {
            for cx in (px - reach).div_euclid(res)..=(px + reach).div_euclid(res) {
                let d2 = cspace::square_dist2(px, py, cx, cy, res);
                if d2 > reach * reach || !cspace::cell_blocks(map, cx as i32, cy as i32, false) {
                    continue;
                }
                let corner = ((cx * res) as i32, (hmm - (cy + 1) * res) as i32);
                keep_nearest(&mut best, d2, corner);
            }
        }
        let mut corners = Vec::new();
        for &(_, c) in &best {
            // Same capacity: cannot fail (`collect` would panic if it did).
            let _ = corners.push(c);
        }
        Self {
            corners,
            res_mm: res as i32,
        }
    }

    /// The cells' squares, nearest first: (south-west corner, side), mm.
    pub fn squares(&self) -> impl Iterator<Item = ((i32, i32), i32)> + '_ {
        self.corners.iter().map(move |&c| (c, self.res_mm))
    }

    /// Points on the squares' outlines (world mm), [`OUTLINE_STEPS`] + 1
    /// along each side (corners included). The guard counts them as wall
    /// points: a corner beside the path that no beam of the last
    /// revolution struck is still in the way. The free distance they
    /// give is within the integer frame's rounding of the true first
    /// contact (property-tested; the guard keeps a 20 mm reserve).
    pub fn outline_points(&self) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.outline_points_beside((0, 0), 0)
    }

    /// [`Self::outline_points`] of the squares farther than `under_mm`
    /// from `here` (world mm): those nearer lie under the body.
    pub fn outline_points_beside(
        &self,
        here: (i32, i32),
        under_mm: i64,
    ) -> impl Iterator<Item = (i32, i32)> + '_ {
        let (px, py) = (here.0 as i64, here.1 as i64);
        let beside = move |&((x0, y0), side): &((i32, i32), i32)| {
            let (x0, y0, s) = (x0 as i64, y0 as i64, side as i64);
            let dx = (x0 - px).max(0).max(px - (x0 + s));
            let dy = (y0 - py).max(0).max(py - (y0 + s));
            dx * dx + dy * dy >= under_mm * under_mm
        };
        self.squares().filter(beside).flat_map(|((x0, y0), side)| {
            let (x1, y1) = (x0.saturating_add(side), y0.saturating_add(side));
            (0..OUTLINE_STEPS).flat_map(move |i| {
                let t = side * i / OUTLINE_STEPS;
                [(x0 + t, y0), (x1, y0 + t), (x1 - t, y1), (x0, y1 - t)]
            })
        })
    }
}

/// Inserts (`d2`, `corner`) into `best` (sorted, nearest first), dropping
/// the farthest when full.
fn keep_nearest(best: &mut Vec<(i64, (i32, i32)), NEAR_CELLS>, d2: i64, corner: (i32, i32)) {
    let at = best.iter().position(|&(d, _)| d2 < d).unwrap_or(best.len());
    if at >= NEAR_CELLS {
        return;
    }
    if best.is_full() {
        best.pop();
    }
    // Not full now, and `at` ≤ len: cannot fail.
    let _ = best.insert(at, (d2, corner));
}

/// How far inside `keep_mm` the rim (radius `radius_mm`) is of the nearest
/// wall beside it on the left and on the right, mm (0: none). A square
/// counts when its point nearest the centre lies at least 27° off the
/// heading (|y| ≥ x/2) and not behind the body's middle (x ≥ −radius/2).
pub fn intrusions(p: &KeepOffParams, walls: &NearWalls, pose: &Pose, radius_mm: i32) -> (i32, i32) {
    let frame = RobotFrame::of(pose);
    let (mut left, mut right) = (0i32, 0i32);
    for ((x0, y0), side) in walls.squares() {
        // max/min, not clamp: no assert on the bounds' order.
        let q = (
            pose.x_mm.max(x0).min(x0.saturating_add(side)),
            pose.y_mm.max(y0).min(y0.saturating_add(side)),
        );
        let (x, y) = frame.to_robot(q);
        if x < -radius_mm / 2 || 2 * (y as i64).abs() < x as i64 {
            continue;
        }
        let (dx, dy) = ((q.0 - pose.x_mm) as i64, (q.1 - pose.y_mm) as i64);
        let d = isqrt_u64((dx * dx + dy * dy) as u64) as i64;
        let inside = (p.keep_mm as i64 - (d - radius_mm as i64))
            .max(0)
            .min(i32::MAX as i64) as i32;
        if y > 0 {
            left = left.max(inside);
        } else {
            right = right.max(inside);
        }
    }
    (left, right)
}

/// The follower's command (`v` mm/s, `w` mrad/s) with the turn away from
/// walls beside the body added; unchanged unless driving forward.
pub fn steer(
    p: &KeepOffParams,
    walls: &NearWalls,
    pose: &Pose,
    radius_mm: i32,
    (v, w): (i32, i32),
) -> (i32, i32) {
    if v <= 0 || p.keep_mm <= 0 {
        return (v, w);
    }
    let (left, right) = intrusions(p, walls, pose, radius_mm);
    let push = (right as i64 - left as i64) * p.gain_mrad_s_per_mm as i64;
    let cap = p.max_w_mrad_s.max(0) as i64;
    let add = push.clamp(-cap, cap) as i32;
    let v = if 2 * left.max(right) > p.keep_mm {
        v.min(p.slow_mm_s.max(0))
    } else {
        v
    };
    (v, w.saturating_add(add))
}
