//! Geometry the executive and the tests share: frames, distances, the
//! corridor test, the disc sweep against the evidence map, and fine-grid
//! helpers. All integer, world millimetres.

use super::cspace;
use super::dwa::PointMm;
use crate::grid::{Cell, Grid};
use crate::math::cost::dist_mm;
use crate::robot::lidar_map::{CellState, EvidenceMap, PRIOR_WALL};
use crate::robot::odometry::Pose;

/// World point into the robot frame (x forward, y left), mm.
pub fn to_robot(pose: &Pose, q: (i32, i32)) -> PointMm {
    RobotFrame::of(pose).to_robot(q)
}

/// `q` lies within `r_mm` of the robot along both axes (world mm): a
/// cheap test that skips far points before their transform.
pub fn within_square(pose: &Pose, q: (i32, i32), r_mm: i64) -> bool {
    (q.0 as i64 - pose.x_mm as i64).abs() <= r_mm && (q.1 as i64 - pose.y_mm as i64).abs() <= r_mm
}

/// A pose's frame with its sine and cosine worked out once, for many
/// points: the guard and DWA turn every lidar point of the ring each
/// period, and a CORDIC per point made the control tick cost over 2 M
/// instructions (measured in the processor-in-the-loop run).
#[derive(Clone, Copy, Debug)]
pub struct RobotFrame {
    x_mm: i32,
    y_mm: i32,
    sin_q30: i64,
    cos_q30: i64,
}

impl RobotFrame {
    /// The frame of `pose`.
    pub fn of(pose: &Pose) -> Self {
        let (s, c) = crate::math::angle::sin_cos_q30(pose.theta_mrad as i64 * 1000);
        Self {
            x_mm: pose.x_mm,
            y_mm: pose.y_mm,
            sin_q30: s,
            cos_q30: c,
        }
    }

    /// World point into this frame (x forward, y left), mm.
    pub fn to_robot(&self, (x, y): (i32, i32)) -> PointMm {
        let (s, c) = (self.sin_q30, self.cos_q30);
        let (dx, dy) = ((x - self.x_mm) as i64, (y - self.y_mm) as i64);
        (
            ((dx * c + dy * s) >> 30) as i32,
            ((dy * c - dx * s) >> 30) as i32,
        )
    }
}

/// The point of segment a-b nearest to `p` (mm): the robot's foot on the
/// line it follows. In i128, so no pose can overflow it.
pub fn foot_on_segment(a: (i32, i32), b: (i32, i32), p: (i32, i32)) -> (i32, i32) {
    let (ux, uy) = ((b.0 as i128 - a.0 as i128), (b.1 as i128 - a.1 as i128));
    let len2 = ux * ux + uy * uy;
    let (px, py) = ((p.0 as i128 - a.0 as i128), (p.1 as i128 - a.1 as i128));
    let dot = (px * ux + py * uy).clamp(0, len2);
    let step = |u: i128| u.saturating_mul(dot).checked_div(len2).unwrap_or(0);
    // Between a and b, so back in i32 range.
    (
        (a.0 as i128 + step(ux)) as i32,
        (a.1 as i128 + step(uy)) as i32,
    )
}

/// The point `d_mm` from `a` toward `b`, or `b` when that is nearer.
pub fn toward(a: (i32, i32), b: (i32, i32), d_mm: i64) -> (i32, i32) {
    let total = dist_mm(a, b);
    if total <= d_mm || total == 0 {
        return b;
    }
    (
        a.0 + ((b.0 as i64 - a.0 as i64) * d_mm / total) as i32,
        a.1 + ((b.1 as i64 - a.1 as i64) * d_mm / total) as i32,
    )
}

/// True when `q` lies within `reach` of segment a→b, beyond a's end.
pub fn in_corridor(a: (i32, i32), b: (i32, i32), q: (i32, i32), reach: i64) -> bool {
    let (ux, uy) = ((b.0 - a.0) as i64, (b.1 - a.1) as i64);
    let (qx, qy) = ((q.0 - a.0) as i64, (q.1 - a.1) as i64);
    let len2 = ux * ux + uy * uy;
    let dot = qx * ux + qy * uy;
    if dot <= 0 || len2 == 0 {
        return false;
    }
    let (px, py) = if dot >= len2 {
        (qx - ux, qy - uy)
    } else {
        // Perpendicular distance² = cross² / len².
        let cross = qx * uy - qy * ux;
        return (cross as i128 * cross as i128) < (reach * reach) as i128 * len2 as i128;
    };
    px * px + py * py < reach * reach
}

/// True when the map explains a lidar point: an occupied cell within two
/// cells of it (100 mm: odometry drift over a room's length), or the point
/// lies where the map knows nothing yet (new map, not an intruder). A point
/// is unexplained only in space the map has seen free: a person, a moved
/// chair.
pub fn explained<const EV: usize>(map: &EvidenceMap<EV>, q: (i32, i32)) -> bool {
    let (cx, cy) = map.cell_of(q.0, q.1);
    map.state(cx, cy) == CellState::Unknown
        || (-2..=2).any(|dy| (-2..=2).any(|dx| map.state(cx + dx, cy + dy) == CellState::Occupied))
}

/// The wall surface a mapped lidar point stands for, as an offset from
/// the point (mm): of the occupied cells within one cell of `q`, the one
/// nearest `q`, and of that cell's square the point nearest `from` (the
/// robot). `None` when no occupied cell's square lies within `tol_mm` of
/// `q` (the caller's 2.5 σ of the range noise: 25 mm for the LD06's
/// 10 mm): a hit farther in front of the wall is something else (a
/// person, a chair the map lacks, a person standing on their own stale
/// marks) and stands for itself.
///
/// Why: the guard judged mapped points a noise σ inside its corridor's
/// edge ([`crate::nav::guard::GuardParams::mapped_slack_mm`]), or every
/// wall passed 10 mm away would stop the robot; but then a convex corner
/// (a door jamb) 2 to 10 mm from the body's path was not seen either,
/// and every wall contact in the real-home missions was such a corner;
/// and along a wall the plan passes 10 mm from the body, the 2 σ
/// outliers of hundreds of hits still stopped the robot every few
/// centimetres. Every point of an occupied cell's square is wall,
/// exactly, when the pose is right; the one nearest the robot is the
/// most cautious choice, and it carries no range noise, so the guard
/// judges it at full width instead of the hit.
/// Within one cell the offset fits an `i8` on each axis (≤ 2 cells).
///
/// `fixed_only` (known mode): only fixed walls ([`PRIOR_WALL`]: the prior
/// map, the bumper's marks) are stood for. What known mode maps beside
/// the prior is a person or a moved chair, mapped a few revolutions late
/// and a cell coarse: a person's hits 10–25 mm in front of their stale
/// square were moved onto it, 5 mm outside the guard's corridor, and the
/// body drove into a person standing beside its lane (the z10 home,
/// known mode, realistic, 1 person, seed 2, 3,368 s). Such hits stand
/// for themselves.
pub fn wall_offset<const EV: usize>(
    map: &EvidenceMap<EV>,
    q: (i32, i32),
    from: (i32, i32),
    tol_mm: i32,
    fixed_only: bool,
) -> Option<[i8; 2]> {
    let r = map.res_mm().max(1) as i64;
    let (cx, cy) = map.cell_of(q.0, q.1);
    let mut best: Option<(i64, (i64, i64))> = None;
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (x, y) = (cx + dx, cy + dy);
            let movable = fixed_only && map.evidence(x, y) != PRIOR_WALL;
            if movable || map.state(x, y) != CellState::Occupied {
                continue;
            }
            // The square [x0, x0 + r] × [y0, y0 + r], world mm.
            let (mx, my) = cspace::fine_centre_mm(map, x, y);
            let (x0, y0) = (mx as i64 - r / 2, my as i64 - r / 2);
            // `max`/`min`, not `clamp`: clamp asserts its bounds' order,
            // a panicking branch in the firmware (issue 11 §6).
            let near = |p: (i64, i64)| (p.0.max(x0).min(x0 + r), p.1.max(y0).min(y0 + r));
            let at = near((q.0 as i64, q.1 as i64));
            let d2 = (at.0 - q.0 as i64).pow(2) + (at.1 - q.1 as i64).pow(2);
            if best.is_none_or(|b| d2 < b.0) {
                best = Some((d2, near((from.0 as i64, from.1 as i64))));
            }
        }
    }
    let tol = tol_mm.max(0) as i64;
    let (_, w) = best.filter(|b| b.0 <= tol * tol)?;
    let off = |a: i64, b: i32| i8::try_from(a - b as i64).ok();
    Some([off(w.0, q.0)?, off(w.1, q.1)?])
}

/// True when a disc of `radius_mm` slides from `a` to `b` (world mm)
/// without overlapping an occupied evidence cell (unknown counts as free),
/// checked every quarter cell.
pub fn segment_clear<const EV: usize>(
    map: &EvidenceMap<EV>,
    a: (i32, i32),
    b: (i32, i32),
    radius_mm: i64,
) -> bool {
    slides(map, a, b, |x, y| {
        cspace::disc_blocked(map, x, y, radius_mm, false)
    })
}

/// [`segment_clear`], against the cells sure to block only
/// ([`cspace::disc_surely_blocked`]).
pub fn segment_surely_clear<const EV: usize>(
    map: &EvidenceMap<EV>,
    a: (i32, i32),
    b: (i32, i32),
    radius_mm: i64,
    at_least: i8,
) -> bool {
    slides(map, a, b, |x, y| {
        cspace::disc_surely_blocked(map, x, y, radius_mm, at_least)
    })
}

/// True when `blocked` (a disc at an index-space point) holds nowhere on
/// the segment a–b (world mm), checked every quarter cell.
fn slides<const EV: usize>(
    map: &EvidenceMap<EV>,
    a: (i32, i32),
    b: (i32, i32),
    blocked: impl Fn(i64, i64) -> bool,
) -> bool {
    let res = map.res_mm().max(1) as i64;
    let hmm = map.height() as i64 * res;
    along(a, b, res, |x, y| !blocked(x, hmm - y))
}

/// True when `ok` holds at every point of the segment `a`-`b` (mm),
/// sampled four times per evidence cell of `res_mm`, both ends included
/// (it stops at the first point where `ok` fails).
pub fn along(
    a: (i32, i32),
    b: (i32, i32),
    res_mm: i64,
    mut ok: impl FnMut(i64, i64) -> bool,
) -> bool {
    let steps = (dist_mm(a, b) * 4 / res_mm.max(1)).max(1);
    // `checked_div`: no overflow branch for the panic check to find.
    let at = |from: i32, to: i32, k: i64| {
        from as i64 + ((to - from) as i64 * k).checked_div(steps).unwrap_or(0)
    };
    (0..=steps).all(|k| ok(at(a.0, b.0, k), at(a.1, b.1, k)))
}

/// The free fine cell nearest to world point `p` within `reach` cells.
pub fn nearest_free_fine_within<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    fine: &Grid<GW>,
    p: (i32, i32),
    reach: i32,
) -> Option<Cell> {
    nearest_fine_where(map, fine, p, reach, |_, _| true)
}

/// Where a search starts from the robot at world point `p`: the free fine
/// cell nearest to it within `reach` cells that is not in a pocket
/// ([`in_pocket`]). Only starts skip pockets: a goal in one is left to the
/// search, which reports it unreachable (a goal moved out of its pocket
/// sent the robot to clean beside a cell it could not reach, again and
/// again: +26 to +72 % mission time on two real homes).
pub fn search_start_fine<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    fine: &Grid<GW>,
    p: (i32, i32),
    reach: i32,
) -> Option<Cell> {
    nearest_fine_where(map, fine, p, reach, |x, y| !in_pocket(fine, x, y))
}

/// The free fine cell nearest to `p` within `reach` cells for which `ok`
/// holds (asked only of cells nearer than the best so far).
fn nearest_fine_where<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    fine: &Grid<GW>,
    p: (i32, i32),
    reach: i32,
    ok: impl Fn(i32, i32) -> bool,
) -> Option<Cell> {
    let (cx, cy) = map.cell_of(p.0, p.1);
    let mut best: Option<(i64, Cell)> = None;
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            let (x, y) = (cx + dx, cy + dy);
            if !fine.is_free(x, y) {
                continue;
            }
            let d = dist_mm(cspace::fine_centre_mm(map, x, y), p);
            if best.is_none_or(|(b, _)| d < b) && ok(x, y) {
                best = Cell::from_xy(x, y).map(|c| (d, c));
            }
        }
    }
    best.map(|(_, c)| c)
}

/// Free cells a component must reach before [`in_pocket`] calls it open.
pub const POCKET_CELLS: usize = 16;

/// True when free fine cell (x, y) lies in a pocket: a 4-connected free
/// component of fewer than [`POCKET_CELLS`] cells. A search from a pocket
/// ends at once with no path, every time, so a robot standing on one
/// waited there for ever (the mission ended `Failed(NoWayHome)`): a cell
/// whose centre clears every obstacle by the body's clearance while all
/// its neighbours do not (between chair legs at the wrong spacing; the
/// corner-berth experiment of stop 56 left many). The robot is inside
/// its clearance there, not inside a wall, so a search starts from the
/// nearest open cell instead and the follower drives it out. Work: a
/// bounded flood fill, at most `POCKET_CELLS`² comparisons.
pub fn in_pocket<const GW: usize>(fine: &Grid<GW>, x: i32, y: i32) -> bool {
    // Cells, not i32 pairs: 64 bytes of stack inside the plan step.
    let Some(start) = Cell::from_xy(x, y) else {
        return false;
    };
    let mut seen = [start; POCKET_CELLS];
    let (mut n, mut head) = (1usize, 0usize);
    while let Some(&c) = seen.get(head).filter(|_| head < n) {
        head += 1;
        let (cx, cy) = (c.x as i32, c.y as i32);
        for (nx, ny) in [(cx + 1, cy), (cx - 1, cy), (cx, cy + 1), (cx, cy - 1)] {
            let Some(next) = Cell::from_xy(nx, ny).filter(|_| fine.is_free(nx, ny)) else {
                continue;
            };
            if seen.get(..n).is_some_and(|s| s.contains(&next)) {
                continue;
            }
            match seen.get_mut(n) {
                Some(slot) => *slot = next,
                None => return false,
            }
            n += 1;
        }
    }
    n < POCKET_CELLS
}

/// Shortens a fine-grid path in place: from each kept point, the farthest
/// of the points 40, 20, 10, 5 and 2 cells on that a disc of `radius_mm`
/// reaches in a straight line ([`segment_clear`]), else the next point.
/// Returns the new length. Work: at most 5 segment checks per kept point.
pub fn prune_clear<const EV: usize>(
    map: &EvidenceMap<EV>,
    path: &mut [Cell],
    radius_mm: i64,
) -> usize {
    let n = path.len();
    if n <= 2 {
        return n;
    }
    let centre = |c: Cell| cspace::fine_centre_mm(map, c.x as i32, c.y as i32);
    let (mut k, mut out) = (0usize, 1usize);
    while k + 1 < n {
        let Some(&cur) = path.get(k) else { break };
        let mut next = k + 1;
        for hop in [40usize, 20, 10, 5, 2] {
            let i = (k + hop).min(n - 1);
            if i <= k + 1 {
                continue;
            }
            if let Some(&c) = path.get(i) {
                if segment_clear(map, centre(cur), centre(c), radius_mm) {
                    next = i;
                    break;
                }
            }
        }
        if let Some(&c) = path.get(next) {
            if let Some(slot) = path.get_mut(out) {
                *slot = c;
            }
        }
        out += 1;
        k = next;
    }
    out
}

/// The free fine cell nearest to world point `p` within 3 cells.
pub fn nearest_free_fine<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    fine: &Grid<GW>,
    p: (i32, i32),
) -> Option<Cell> {
    nearest_free_fine_within(map, fine, p, 3)
}

/// True when every fine cell the straight line from `a` to `b` (world mm)
/// passes over, checked every quarter cell, is free on the fine
/// configuration space.
pub fn fine_segment_clear<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    fine: &Grid<GW>,
    a: (i32, i32),
    b: (i32, i32),
) -> bool {
    along(a, b, map.res_mm() as i64, |x, y| {
        let (cx, cy) = map.cell_of(x as i32, y as i32);
        fine.is_free(cx, cy)
    })
}
