//! Wide searches for when the pose guess may be far off: an exhaustive
//! correlative search over a window (the start: the robot put down by a
//! person within ±0.2 m and ±15° of the dock), or over every free place
//! of the map (a kidnap), on the coarse levels, keeping the best few
//! candidates for Gauss–Newton to settle (Olson, "Real-Time Correlative
//! Scan Matching", ICRA 2009: score every pose of a grid on a blurred
//! map; Hess et al. 2016 seed their optimiser with it the same way).
//!
//! Work bounds: the start's window costs 15 headings × 49 offsets × 56
//! points samples on the 20 cm level, then 12 × 27 × 112 on the 10 cm
//! one. The global search (headings outer, so the rotated points are
//! computed once per heading) costs at most 60 headings × free places at
//! 20 cm × 64 points block tests (a place is dropped at the first miss
//! that leaves it below the kept candidates), then [`GLOBAL_TOP`] windows
//! of 3 × 9 poses on the 20 cm level, [`TOP`] of 3 × 9 on the 10 cm one,
//! and [`TOP`] refinements. On the emulated Cortex-M4, a 48 m² flat:
//! 82 M instructions in all, about 45 M, 11 M, 10 M and 14 M.

use super::field::Field;
use super::gauss_newton::{facing, refine};
use super::points::{place, Pt};
use super::pyramid::Level;
use super::{Match, PoseU};
use crate::math::angle::sin_cos_q30;
use crate::robot::lidar_map::{CellState, EvidenceMap};

/// Candidates kept for refinement.
pub const TOP: usize = 12;
/// Points used by the global search's coarse score. Twin scans at 50
/// random free places of each of the six real homes, relocalised over the
/// whole map: 32 points found 291 of 300, 64 points 296, none wrong
/// either way; 45 M against 27 M instructions on the emulated M4 (48 m²
/// flat).
const GLOBAL_POINTS: usize = 64;
/// Heading steps of the global search (6° apart).
const GLOBAL_HEADINGS: i64 = 60;

/// A kept candidate, 16 bytes: its heading wrapped to ±π in an `i32` of
/// µrad ([`PoseU`]'s `i64` would make it 24). The whole-map search keeps
/// [`GLOBAL_TOP`] of them on the stack.
#[derive(Clone, Copy, Debug)]
struct Cand {
    score: u32,
    x_mm: i32,
    y_mm: i32,
    theta_urad: i32,
}

impl Cand {
    fn of(score: u32, pose: PoseU) -> Self {
        Self {
            score,
            x_mm: pose.x_mm,
            y_mm: pose.y_mm,
            // Within ±3 141 593 µrad once wrapped.
            theta_urad: wrap_urad(pose.theta_urad) as i32,
        }
    }

    fn pose(&self) -> PoseU {
        PoseU {
            x_mm: self.x_mm,
            y_mm: self.y_mm,
            theta_urad: self.theta_urad as i64,
        }
    }
}

/// The best candidates so far, by score (highest first is not kept; the
/// lowest is replaced).
#[derive(Clone, Copy, Debug)]
pub struct TopK<const N: usize = TOP> {
    items: [Cand; N],
    len: usize,
    /// The lowest score kept once full, 0 before ([`TopK::floor`]), kept
    /// up to date by [`TopK::offer`]: the whole-map search asks for it at
    /// every place and heading.
    floor: u32,
}

impl<const N: usize> Default for TopK<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> TopK<N> {
    /// Empty.
    pub const fn new() -> Self {
        Self {
            items: [Cand {
                score: 0,
                x_mm: 0,
                y_mm: 0,
                theta_urad: 0,
            }; N],
            len: 0,
            floor: 0,
        }
    }

    /// Offers a candidate. Candidates within 120 mm and 60 mrad of a kept
    /// one compete with it alone (non-maximum suppression), so the few
    /// kept are distinct basins, not one basin's neighbours.
    pub fn offer(&mut self, score: u32, pose: PoseU) {
        // Full, a score at or below the floor changes nothing: it cannot
        // replace the worst, nor beat a near candidate (all score above).
        if self.len == N && score <= self.floor {
            return;
        }
        self.insert(Cand::of(score, pose));
        if self.len == N {
            self.floor = self.kept().iter().map(|c| c.score).min().unwrap_or(0);
        }
    }

    /// [`TopK::offer`] without the floor's upkeep.
    fn insert(&mut self, c: Cand) {
        let items = self.items.get_mut(..self.len).unwrap_or(&mut []);
        let near = items.iter_mut().find(|p| {
            (p.x_mm - c.x_mm).abs() <= 120
                && (p.y_mm - c.y_mm).abs() <= 120
                && wrap_urad(p.theta_urad as i64 - c.theta_urad as i64).abs() <= 60_000
        });
        if let Some(n) = near {
            if n.score < c.score {
                *n = c;
            }
            return;
        }
        if let Some(slot) = self.items.get_mut(self.len) {
            *slot = c;
            self.len += 1;
            return;
        }
        let worst = self
            .items
            .iter_mut()
            .min_by_key(|p| p.score)
            .filter(|p| p.score < c.score);
        if let Some(w) = worst {
            *w = c;
        }
    }

    /// The lowest score kept once full (a new candidate must beat it), 0
    /// before.
    pub fn floor(&self) -> u32 {
        self.floor
    }

    fn kept(&self) -> &[Cand] {
        self.items.get(..self.len).unwrap_or(&[])
    }

    /// The candidates kept: (score, pose).
    pub fn iter(&self) -> impl Iterator<Item = (u32, PoseU)> + '_ {
        self.kept().iter().map(|c| (c.score, c.pose()))
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

/// Candidates the whole-map search keeps ([`global`]). With 12, the S8
/// home's kidnap spot (beside a long wall, clutter across the home
/// scoring as well on the coarse level) was never kept; 48 keep it, and
/// a cheap window on the 20 cm level ([`CANDIDATE_WINDOW`]) picks the
/// best [`TOP`] of them for the 10 cm level.
pub const GLOBAL_TOP: usize = 48;
/// The window around each candidate of the global search (its grid is
/// 200 mm and 6°), on the 20 cm level: ±3° in 3° steps, ±100 mm in 100 mm
/// steps; the best [`TOP`] are then sharpened on the 10 cm level by
/// [`SHARPEN_WINDOW`].
pub const CANDIDATE_WINDOW: Window = Window {
    turns: 1,
    turn_urad: 52_360,
    steps: 1,
    step_mm: 100,
    stride: 8,
};

/// Scores the window `w` of poses around `guess` on `field` by
/// [`face_score`], handing each (score, pose) to `offer`.
pub fn window<const EV: usize, const MW: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    guess: PoseU,
    w: &Window,
    mut offer: impl FnMut(u32, PoseU),
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
                offer(face_score(field, pts, &pose, sc, w.stride), pose);
            }
        }
    }
}

/// Candidates of a coarser search, each replaced by the best pose of the
/// window `w` around it on `field` ([`CANDIDATE_WINDOW`] after the global
/// search, [`SHARPEN_WINDOW`] after the start's).
pub fn sharpen<const EV: usize, const MW: usize, const N: usize>(
    field: &Field<'_, EV, MW>,
    pts: &[Pt],
    coarse: &TopK<N>,
    w: &Window,
) -> TopK {
    let mut out = TopK::new();
    for (_, pose) in coarse.iter() {
        // The window's best (the first of equals).
        let mut best: Option<(u32, PoseU)> = None;
        window(field, pts, pose, w, |s, p| {
            if best.is_none_or(|(b, _)| s > b) {
                best = Some((s, p));
            }
        });
        if let Some((s, p)) = best {
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
// Not inlined: inlined into `Fusion::relocalise`, the whole-map
// relocalisation took 89.8 M instructions on the emulated M4, 82.4 M
// apart.
#[inline(never)]
pub fn global<const EV: usize, const N: usize>(
    level: &Level<'_>,
    map: &EvidenceMap<EV>,
    pts: &[Pt],
) -> TopK<N> {
    let mut top = TopK::new();
    let k = pts.len().div_ceil(GLOBAL_POINTS).max(1);
    // Bounded so that `block` is positive: no division by zero linked in.
    let res = map.res_mm().clamp(1, 10_000) as i32;
    let block = 8 * res;
    // Per point: block offsets (x even, x odd, row even, row odd).
    // i16: a block is 40 cm at 5 cm cells, so ±13 km; 512 bytes of stack.
    let mut off = [(0i16, 0i16, 0i16, 0i16); GLOBAL_POINTS];
    let zero = PoseU::default();
    for ih in 0..GLOBAL_HEADINGS {
        let theta = ih * 6_283_185 / GLOBAL_HEADINGS;
        let sc = sin_cos_q30(theta);
        let mut n = 0;
        for (slot, &p) in off.iter_mut().zip(pts.iter().step_by(k)) {
            let (rx, ry) = place(&zero, sc, p);
            let o = |par: i32, d: i32| {
                let b = (par * 4 * res + res / 2 + d)
                    .checked_div_euclid(block)
                    .unwrap_or(0);
                b.clamp(i16::MIN.into(), i16::MAX.into()) as i16
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
                // Bound: a place is dropped as soon as its misses leave
                // it below the kept candidates' floor.
                let spare = off.len().saturating_sub(top.floor() as usize);
                let mut misses = 0;
                for o in off {
                    let ox = if px { o.1 } else { o.0 };
                    let oy = if py { o.3 } else { o.2 };
                    if level.share(bx + i32::from(ox), by + i32::from(oy)) == 0 {
                        misses += 1;
                        if misses > spare {
                            break;
                        }
                    }
                }
                if misses > spare {
                    continue;
                }
                let score = off.len() - misses;
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
    // (face score on the finest level, pose, inliers): 24 bytes each on
    // the stack, a whole `Match` 64.
    let mut results = [(0u32, PoseU::default(), 0u32); TOP];
    let mut n = 0;
    for (slot, (_, pose)) in results.iter_mut().zip(top.iter()) {
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
        *slot = (score, p, inliers);
        n += 1;
    }
    let results = results.get(..n).unwrap_or(&[]);
    let best = results.iter().max_by_key(|r| r.0).copied();
    let runner = best.and_then(|(_, b, _)| {
        results
            .iter()
            .filter(|(_, m, _)| {
                let d =
                    (m.x_mm as i64 - b.x_mm as i64).abs() + (m.y_mm as i64 - b.y_mm as i64).abs();
                let dt = wrap_urad(m.theta_urad - b.theta_urad).abs();
                d > 300 || dt > 300_000
            })
            .max_by_key(|r| r.0)
            .copied()
    });
    let as_match = |(_, pose, inliers): (u32, PoseU, u32)| Match {
        pose,
        inliers,
        points: pts.len() as u32,
        ..Match::default()
    };
    (best.map(as_match), runner.map(as_match))
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
