//! An independent checker of coverage runs: given the map and the driven
//! waypoints alone, it verifies that no segment enters an obstacle or cuts a
//! corner, and recomputes the cell counts of [`crate::verify::metrics`] without
//! using its code.
//!
//! Where the metrics walk the supercover line, the checker tests every cell
//! of a segment's bounding box for an exact intersection of the segment with
//! the cell's closed square (integer arithmetic in doubled coordinates);
//! where the metrics count reachable cells by 4-connected sweeps, the checker
//! applies the 8-connected, no-corner-cutting rule literally. The two must
//! agree; the host tests and the emulated run check that they do. Lengths
//! and rotation are recomputed in floating point by the host tests.

use crate::grid::{Cell, Grid};
use crate::math::bits::Bits;
use crate::verify::metrics::SegmentKind;

/// What the checker found wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CheckError {
    /// The start is blocked or off the map.
    BadStart,
    /// A segment touches a blocked or off-map cell (or cuts its corner).
    HitsObstacle {
        /// Segment start.
        from: Cell,
        /// Segment end.
        to: Cell,
        /// The blocked cell touched.
        cell: Cell,
    },
}

/// Counts recomputed by the checker.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Checked {
    /// Free cells reachable from the start.
    pub reachable_cells: u32,
    /// Distinct cells touched.
    pub covered_cells: u32,
    /// Reachable cells never touched.
    pub missed_cells: u32,
    /// Visits beyond the first.
    pub repeated_cells: u32,
    /// Heading changes.
    pub turns: u32,
    /// Cover segments.
    pub segments: u32,
    /// Waypoints after the start.
    pub moves: u32,
}

/// A streaming checker for maps of up to `NW * 32` cells.
pub struct Checker<const NW: usize> {
    touched: Bits<NW>,
    reach: Bits<NW>,
    out: Checked,
    last: Cell,
    last_dir: (i64, i64),
    last_kind: Option<SegmentKind>,
    width: u32,
}

impl<const NW: usize> Default for Checker<NW> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NW: usize> Checker<NW> {
    /// An empty checker.
    pub const fn new() -> Self {
        Self {
            touched: Bits::new(),
            reach: Bits::new(),
            out: Checked {
                reachable_cells: 0,
                covered_cells: 0,
                missed_cells: 0,
                repeated_cells: 0,
                turns: 0,
                segments: 0,
                moves: 0,
            },
            last: Cell::new(0, 0),
            last_dir: (0, 0),
            last_kind: None,
            width: 0,
        }
    }

    /// Starts checking a run from `start` on `grid` (whose obstacles are
    /// the truth the run is checked against).
    pub fn start<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        start: Cell,
    ) -> Result<(), CheckError> {
        *self = Self::new();
        self.width = grid.width();
        let (sx, sy) = start.xy();
        let Some(si) = grid.index(sx, sy).filter(|_| grid.is_free(sx, sy)) else {
            return Err(CheckError::BadStart);
        };
        // Reachability, 8-connected without corner cutting, by relaxation.
        self.reach.put(si, true);
        let (w, h) = (grid.width() as i32, grid.height() as i32);
        let mut changed = true;
        while changed {
            changed = false;
            for y in 0..h {
                for x in 0..w {
                    let Some(i) = grid.index(x, y) else { continue };
                    if self.reach.get(i) || grid.is_blocked(x, y) {
                        continue;
                    }
                    let mut ok = false;
                    for dy in -1..=1 {
                        for dx in -1..=1 {
                            if (dx, dy) == (0, 0) {
                                continue;
                            }
                            let Some(j) = grid.index(x + dx, y + dy) else {
                                continue;
                            };
                            if !self.reach.get(j) {
                                continue;
                            }
                            if dx != 0
                                && dy != 0
                                && (grid.is_blocked(x + dx, y) || grid.is_blocked(x, y + dy))
                            {
                                continue;
                            }
                            ok = true;
                        }
                    }
                    if ok {
                        self.reach.put(i, true);
                        changed = true;
                    }
                }
            }
        }
        self.out.reachable_cells = self.reach.count_prefix(grid.cells()) as u32;
        self.touched.put(si, true);
        self.out.covered_cells = 1;
        self.last = start;
        Ok(())
    }

    /// Checks and counts the segment from the last waypoint to `to`.
    pub fn push<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        to: Cell,
        kind: SegmentKind,
        starts_segment: bool,
    ) -> Result<(), CheckError> {
        let from = self.last;
        if to == from {
            return Ok(());
        }
        self.out.moves += 1;
        if kind == SegmentKind::Cover
            && (starts_segment || self.last_kind != Some(SegmentKind::Cover))
        {
            self.out.segments += 1;
        }
        let dir = (to.x as i64 - from.x as i64, to.y as i64 - from.y as i64);
        let (px, py) = self.last_dir;
        if (px, py) != (0, 0) && (px * dir.1 - py * dir.0 != 0 || px * dir.0 + py * dir.1 < 0) {
            self.out.turns += 1;
        }
        let mut hit = None;
        let (touched, out) = (&mut self.touched, &mut self.out);
        touched_cells(from, to, |x, y| {
            if grid.is_blocked(x, y) {
                hit = Cell::from_xy(x, y).or(Some(from));
                return false;
            }
            if (x, y) != from.xy() {
                // (the first cell was visited by the previous segment)
                if let Some(i) = grid.index(x, y) {
                    if touched.get(i) {
                        out.repeated_cells += 1;
                    } else {
                        touched.put(i, true);
                        out.covered_cells += 1;
                    }
                }
            }
            true
        });
        if let Some(cell) = hit {
            return Err(CheckError::HitsObstacle { from, to, cell });
        }
        self.last = to;
        self.last_dir = dir;
        self.last_kind = Some(kind);
        Ok(())
    }

    /// The counts, with the reachable cells never touched.
    pub fn finish<const GW: usize>(&mut self, grid: &Grid<GW>) -> Checked {
        let mut missed = 0u32;
        for i in 0..grid.cells() {
            if self.reach.get(i) && !self.touched.get(i) {
                missed += 1;
            }
        }
        self.out.missed_cells = missed;
        self.out
    }
}

/// Calls `visit(x, y)` for every cell whose closed square meets the segment
/// between the centres of `from` and `to`, exactly (integer arithmetic in
/// doubled coordinates: a square is met when its bounding box overlaps the
/// segment's and its four corners are not all strictly on one side of the
/// line). Stops early when `visit` returns false; returns false then.
pub fn touched_cells(from: Cell, to: Cell, mut visit: impl FnMut(i32, i32) -> bool) -> bool {
    let (ax, ay) = (2 * from.x as i64 + 1, 2 * from.y as i64 + 1);
    let (bx, by) = (2 * to.x as i64 + 1, 2 * to.y as i64 + 1);
    let side = |x: i64, y: i64| ((bx - ax) * (y - ay) - (by - ay) * (x - ax)).signum();
    let (x0, x1) = (from.x.min(to.x) as i64 - 1, from.x.max(to.x) as i64 + 1);
    let (y0, y1) = (from.y.min(to.y) as i64 - 1, from.y.max(to.y) as i64 + 1);
    for cy in y0..=y1 {
        for cx in x0..=x1 {
            let (lx, hx, ly, hy) = (2 * cx, 2 * cx + 2, 2 * cy, 2 * cy + 2);
            if hx < ax.min(bx) || lx > ax.max(bx) || hy < ay.min(by) || ly > ay.max(by) {
                continue;
            }
            let s = [side(lx, ly), side(hx, ly), side(lx, hy), side(hx, hy)];
            if s.iter().all(|&v| v > 0) || s.iter().all(|&v| v < 0) {
                continue;
            }
            if !visit(cx as i32, cy as i32) {
                return false;
            }
        }
    }
    true
}
