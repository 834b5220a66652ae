//! Wide searches for when the pose guess may be far off: an exhaustive
//! correlative search over a window (the start: the robot put down by a
//! person within ±0.2 m and ±15° of the dock), or over every free place
//! of the map (a kidnap), on the coarse levels, keeping the best few
//! candidates for Gauss–Newton to settle (Olson, "Real-Time Correlative
//! Scan Matching", ICRA 2009: score every pose of a grid on a blurred
//! map; Hess et al. 2016 seed their optimiser with it the same way).
//!
//! Work bounds: the start's window costs 15 headings × 49 offsets × 56
//! points samples on the 20 cm level, then 12 × 27 × 112 on the 10 cm one; the global search (headings outer, so the rotated points are
//! computed once per heading) 60 headings × free places at 20 cm × 48
//! points nearest-cell tests, then [`TOP`] refinements.

use super::field::Field;
use super::gauss_newton::{facing, refine};
use super::points::{place, Pt};
use super::pyramid::Level;
use super::{Match, PoseU};
use crate::math::angle::sin_cos_q30;
use crate::robot::lidar_map::{CellState, EvidenceMap};

/// Candidates kept for refinement.
pub const TOP: usize = 12;
/// Points used by the global search's coarse score.
const GLOBAL_POINTS: usize = 32;
/// Heading steps of the global search (6° apart).
const GLOBAL_HEADINGS: i64 = 60;

/// The best candidates so far, by score (highest first is not kept; the
/// lowest is replaced).
#[derive(Clone, Copy, Debug)]
pub struct TopK {
    items: [(u32, PoseU); TOP],
    len: usize,
}

impl Default for TopK {
    fn default() -> Self {
        Self::new()
    }
}

impl TopK {
    /// Empty.
    pub const fn new() -> Self {
        Self {
            items: [(
                0,
                PoseU {
                    x_mm: 0,
                    y_mm: 0,
                    theta_urad: 0,
                },
            ); TOP],
            len: 0,
        }
    }

    /// Offers a candidate. Candidates within 120 mm and 60 mrad of a kept
    /// one compete with it alone (non-maximum suppression), so the few
    /// kept are distinct basins, not one basin's neighbours.
    pub fn offer(&mut self, score: u32, pose: PoseU) {
        let items = self.items.get_mut(..self.len).unwrap_or(&mut []);
        let near = items.iter_mut().find(|(_, p)| {
            (p.x_mm - pose.x_mm).abs() <= 120
                && (p.y_mm - pose.y_mm).abs() <= 120
                && wrap_urad(p.theta_urad - pose.theta_urad).abs() <= 60_000
        });
        if let Some(n) = near {
            if n.0 < score {
                *n = (score, pose);
            }
            return;
        }
        if let Some(slot) = self.items.get_mut(self.len) {
            *slot = (score, pose);
            self.len += 1;
            return;
        }
        let worst = self
            .items
            .iter_mut()
            .min_by_key(|(s, _)| *s)
            .filter(|(s, _)| *s < score);
        if let Some(w) = worst {
            *w = (score, pose);
        }
    }

    /// The lowest score kept once full (a new candidate must beat it), 0
    /// before.
    pub fn floor(&self) -> u32 {
        if self.len < TOP {
            return 0;
        }
        self.as_slice().iter().map(|c| c.0).min().unwrap_or(0)
    }

    /// The candidates kept.
    pub fn as_slice(&self) -> &[(u32, PoseU)] {
        self.items.get(..self.len).unwrap_or(&[])
    }
}

/// A window of poses: ± `turns` heading steps of `turn_urad`, ± `steps`
/// offsets of `step_mm` on both axes, scoring every `stride`-th point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    /// Heading steps either side.
    pub turns: i64,
    /// Heading step, µrad.
    pub turn_urad: i64,
    /// Offset steps either side.
    pub steps: i32,
    /// Offset step, mm.
    pub step_mm: i32,
    /// Points scored: every `stride`-th.
    pub stride: usize,
}

/// The start's window, first on the 20 cm level: ±14° in 2° steps,
/// ±240 mm in 80 mm steps; its best candidates are then sharpened on the
/// 10 cm level by [`SHARPEN_WINDOW`] (together within that level's basin of
/// every pose in the window, at a tenth of the single fine window's cost).
pub const START_WINDOW: Window = Window {
    turns: 7,
    turn_urad: 34_907,
    steps: 3,
    step_mm: 80,
    stride: 4,
};

/// The sharpening window around a start candidate: ±1° and ±40 mm.
pub const SHARPEN_WINDOW: Window = Window {
    turns: 1,
    turn_urad: 17_453,
    steps: 1,
    step_mm: 40,
    stride: 2,
};

/// The window around each candidate of the global search (its grid is
/// 200 mm and 6°): ±3° in 1° steps, ±100 mm in 50 mm steps.
pub const CANDIDATE_WINDOW: Window = Window {
    turns: 3,
    turn_urad: 17_453,
    steps: 2,
    step_mm: 50,
    stride: 8,
};

/// Scores the window `w` of poses around `guess` on `field` by
/// [`face_score`], into `top`.
pub fn window<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    guess: PoseU,
    w: &Window,
    top: &mut TopK,
) {
    for it in -w.turns..=w.turns {
        let theta = guess.theta_urad + it * w.turn_urad;
        let sc = sin_cos_q30(theta);
        for iy in -w.steps..=w.steps {
            for ix in -w.steps..=w.steps {
                let pose = PoseU {
                    x_mm: guess.x_mm + ix * w.step_mm,
                    y_mm: guess.y_mm + iy * w.step_mm,
                    theta_urad: theta,
                };
                top.offer(face_score(field, pts, &pose, sc, w.stride), pose);
            }
        }
    }
}

/// Candidates of a coarser search, each replaced by the best pose of the
/// window `w` around it on `field` ([`CANDIDATE_WINDOW`] after the global
/// search, [`SHARPEN_WINDOW`] after the start's).
pub fn sharpen<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    coarse: &TopK,
    w: &Window,
) -> TopK {
    let mut out = TopK::new();
    for &(_, pose) in coarse.as_slice() {
        let mut local = TopK::new();
        window(field, pts, pose, w, &mut local);
        if let Some(&(s, p)) = local.as_slice().iter().max_by_key(|c| c.0) {
            out.offer(s, p);
        }
    }
    out
}

/// How well points land on faces: Σ (½ − |M − ½|) in Q8 over every
/// `step`-th point on a face turned toward the lidar (a point on a face
/// scores 128, one in free space, deep in a wall or on a back face 0).
pub fn face_score<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    pose: &PoseU,
    sc: (i64, i64),
    step: usize,
) -> u32 {
    pts.iter()
        .step_by(step.max(1))
        .map(|&p| {
            let (x, y) = place(pose, sc, p);
            let s = field.sample(x, y);
            let beam = ((x - pose.x_mm) as i64, (y - pose.y_mm) as i64);
            if facing(&s, beam.0, beam.1) {
                (128 - (s.m_q8 - 128).abs()).max(0) as u32
            } else {
                0
            }
        })
        .sum()
}

/// The heading among `guess` ± `steps` × `step_urad` whose face score is
/// highest, the position held (tracking's first move: a slip burst turns
/// the robot by a few degrees, which moves far points beyond the fine
/// level's basin).
pub fn best_heading<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    guess: PoseU,
    steps: i64,
    step_urad: i64,
) -> PoseU {
    let mut best = (0u32, guess);
    for i in -steps..=steps {
        let pose = PoseU {
            theta_urad: guess.theta_urad + i * step_urad,
            ..guess
        };
        let score = face_score(field, pts, &pose, sin_cos_q30(pose.theta_urad), 2);
        // Ties keep the heading nearest the guess (i = 0 is tried first
        // among equals only by order; prefer smaller |i|).
        if score > best.0 || (score == best.0 && i == 0) {
            best = (score, pose);
        }
    }
    best.1
}

/// Scores every free place of `map` (every 4th evidence cell: 20 cm) ×
/// 60 headings on the coarsest `level` (blocks of 8 cells, 40 cm) by
/// nearest-block wall hits. Places step by half a block, so a point's
/// block is the place's block plus an offset that depends only on the
/// place's parity: per heading the offsets are computed once, and a hit
/// costs one table read and one level read.
pub fn global<const EV: usize>(level: &Level<'_>, map: &EvidenceMap<EV>, pts: &[Pt]) -> TopK {
    let mut top = TopK::new();
    let k = pts.len().div_ceil(GLOBAL_POINTS).max(1);
    // Bounded so that `block` is positive: no division by zero linked in.
    let res = map.res_mm().clamp(1, 10_000) as i32;
    let block = 8 * res;
    // Per point: block offsets (x even, x odd, row even, row odd).
    let mut off = [(0i32, 0i32, 0i32, 0i32); GLOBAL_POINTS];
    let zero = PoseU::default();
    for ih in 0..GLOBAL_HEADINGS {
        let theta = ih * 6_283_185 / GLOBAL_HEADINGS;
        let sc = sin_cos_q30(theta);
        let mut n = 0;
        for (slot, &p) in off.iter_mut().zip(pts.iter().step_by(k)) {
            let (rx, ry) = place(&zero, sc, p);
            let o = |par: i32, d: i32| {
                (par * 4 * res + res / 2 + d)
                    .checked_div_euclid(block)
                    .unwrap_or(0)
            };
            *slot = (o(0, rx), o(1, rx), o(0, -ry), o(1, -ry));
            n += 1;
        }
        let off = off.get(..n).unwrap_or(&[]);
        for ky in 0..map.height().div_ceil(4) as i32 {
            for kx in 0..map.width().div_ceil(4) as i32 {
                let (cx, cy) = (4 * kx, 4 * ky);
                if map.state(cx, cy) != CellState::Free {
                    continue;
                }
                let (bx, by) = (kx >> 1, ky >> 1);
                let (px, py) = (kx & 1 == 1, ky & 1 == 1);
                let hits = |o: &[(i32, i32, i32, i32)]| {
                    o.iter()
                        .filter(|o| {
                            let ox = if px { o.1 } else { o.0 };
                            let oy = if py { o.3 } else { o.2 };
                            level.share(bx + ox, by + oy) > 0
                        })
                        .count()
                };
                // Bound: a place whose first half cannot reach the kept
                // candidates even with every other point a hit is dropped.
                let (a, b) = off.split_at(off.len() / 2);
                let first = hits(a);
                if ((first + b.len()) as u32) < top.floor() {
                    continue;
                }
                let score = first + hits(b);
                let pose = PoseU {
                    x_mm: cx * res + res / 2,
                    y_mm: (map.height() as i32 - 1 - cy) * res + res / 2,
                    theta_urad: theta,
                };
                top.offer(score as u32, pose);
            }
        }
    }
    top
}

/// Refines each candidate through the levels `fields` (coarse first) and
/// returns the best and the best of those farther than 300 mm or 0.3 rad
/// from it (the runner-up, for the ambiguity test).
pub fn settle<const EV: usize, const MW: usize>(
    fields: &[Field<'_, EV, MW>],
    pts: &[Pt],
    top: &TopK,
) -> (Option<Match>, Option<Match>) {
    // (face score on the finest level, the match)
    let mut results = [(0u32, Match::default()); TOP];
    let mut n = 0;
    for (slot, &(_, pose)) in results.iter_mut().zip(top.as_slice()) {
        let mut p = pose;
        let mut inliers = 0;
        if let Some(f) = fields.first() {
            p = best_heading(f, pts, p, 4, 8_727);
        }
        for f in fields {
            let (q, norm) = refine(f, pts, p, 6);
            p = q;
            inliers = norm.inliers;
        }
        let score = fields
            .last()
            .map_or(0, |f| face_score(f, pts, &p, sin_cos_q30(p.theta_urad), 1));
        let m = Match {
            pose: p,
            inliers,
            points: pts.len() as u32,
            ..Match::default()
        };
        *slot = (score, m);
        n += 1;
    }
    let results = results.get(..n).unwrap_or(&[]);
    let best = results.iter().max_by_key(|r| r.0).copied();
    let runner = best.and_then(|(_, b)| {
        results
            .iter()
            .filter(|(_, m)| {
                let d = (m.pose.x_mm as i64 - b.pose.x_mm as i64).abs()
                    + (m.pose.y_mm as i64 - b.pose.y_mm as i64).abs();
                let dt = wrap_urad(m.pose.theta_urad - b.pose.theta_urad).abs();
                d > 300 || dt > 300_000
            })
            .max_by_key(|r| r.0)
            .map(|r| r.1)
    });
    (best.map(|r| r.1), runner)
}

/// A heading difference wrapped to (−π, π], µrad.
pub fn wrap_urad(t: i64) -> i64 {
    let w = (t + 3_141_593).rem_euclid(6_283_185) - 3_141_593;
    if w == -3_141_593 {
        3_141_592
    } else {
        w
    }
}
