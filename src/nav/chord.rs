//! The edge pass's contour as chords (issue 12, "an edge pass that earns
//! its time"). Ours, not from the papers. The pass walks the fine
//! configuration space's boundary one 5 cm cell at a time; a wall that is
//! not at a multiple of 45° comes out as a staircase of cells, and the
//! follower stops to turn in place wherever a step changes direction by
//! more than its in-place threshold: every few centimetres along a slanted
//! wall or a rounded piece of furniture.
//!
//! The contour cells are gathered into chords: a chord from the last
//! waypoint grows while every cell it passes over stays within `tol_mm` of
//! it and the straight line is clear on the configuration space (so the
//! body never cuts a concave corner into the wall). When the next cell
//! would break either, the last cell held becomes a waypoint. Straight
//! runs of a wall become one sub-path driven at cleaning speed, and the
//! swept strip along the wall loses at most `tol_mm`.

use heapless::Vec;

/// Most contour cells one chord holds (1.2 m at 5 cm).
pub const CHORD_CELLS: usize = 24;

/// A chord being grown.
#[derive(Clone, Debug, Default)]
pub struct Chord {
    /// The chord's points are cleaning moves (along a contour) rather
    /// than a transit's.
    pub cover: bool,
    anchor: (i32, i32),
    held: Vec<(i32, i32), CHORD_CELLS>,
}

impl Chord {
    /// An empty chord at the origin.
    pub const fn new() -> Self {
        Self {
            cover: false,
            anchor: (0, 0),
            held: Vec::new(),
        }
    }

    /// Starts again from waypoint `at` (world mm), dropping what is held.
    pub fn reset(&mut self, at: (i32, i32)) {
        self.anchor = at;
        self.held.clear();
    }

    /// Offers the next contour point (world mm). Returns the waypoint to
    /// drive to when the chord cannot take the point; `clear(a, b)` says
    /// whether the straight line a–b is free (checked on every offer,
    /// cheap), `verify(a, b)` whether the body may sweep it (checked once,
    /// when a chord is cut; [`Chord::cut`]).
    pub fn offer(
        &mut self,
        p: (i32, i32),
        tol_mm: i64,
        clear: impl Fn((i32, i32), (i32, i32)) -> bool,
        verify: impl Fn((i32, i32), (i32, i32)) -> bool,
    ) -> Option<(i32, i32)> {
        let fits = !self.held.is_full()
            && self
                .held
                .iter()
                .all(|&q| off_line(self.anchor, p, q) <= tol_mm)
            && clear(self.anchor, p);
        if fits {
            let _ = self.held.push(p);
            return None;
        }
        let Some(q) = self.cut(verify) else {
            // Not even one step fits: drive to it as it is.
            self.anchor = p;
            return Some(p);
        };
        let _ = self.held.push(p);
        Some(q)
    }

    /// Cuts the chord: the last point held when `verify(anchor, last)`
    /// says the body may sweep the line, else only the first (one contour
    /// step, as the pass walked it), the rest staying held. `None` when
    /// nothing is held. Call until `None` to end the chord.
    pub fn cut(&mut self, verify: impl Fn((i32, i32), (i32, i32)) -> bool) -> Option<(i32, i32)> {
        let last = *self.held.last()?;
        let first = *self.held.first()?;
        if verify(self.anchor, last) {
            self.reset(last);
            return Some(last);
        }
        // Drop the first point (no `collect`: it has a panic path).
        let n = self.held.len();
        for i in 1..n {
            if let Some(v) = self.held.get(i).copied() {
                if let Some(d) = self.held.get_mut(i - 1) {
                    *d = v;
                }
            }
        }
        self.held.truncate(n.saturating_sub(1));
        self.anchor = first;
        Some(first)
    }
}

/// Distance of `q` from the line through `a` and `b`, mm (from `a` when
/// they coincide).
fn off_line(a: (i32, i32), b: (i32, i32), q: (i32, i32)) -> i64 {
    let (ux, uy) = ((b.0 - a.0) as i64, (b.1 - a.1) as i64);
    let (vx, vy) = ((q.0 - a.0) as i64, (q.1 - a.1) as i64);
    let len2 = ux * ux + uy * uy;
    if len2 == 0 {
        return crate::math::cost::isqrt_u64((vx * vx + vy * vy) as u64) as i64;
    }
    let cross = (ux * vy - uy * vx).abs();
    // cross / |u|, rounded up.
    let len = crate::math::cost::isqrt_u64(len2 as u64).max(1) as i64;
    (cross + len - 1) / len
}
