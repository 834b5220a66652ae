//! Conservative line of sight between cell centres (supercover line).
//!
//! ALGORITHMS.md §1 leaves open how the pruning line test treats a robot one
//! cell wide; we decide: **supercover, no corner cutting**. The line from the
//! centre of `a` to the centre of `b` visits every cell whose closed square
//! it touches. Where it passes exactly through a cell corner, *both* side
//! cells are visited as well as the diagonal one, so a line of sight never
//! squeezes between two diagonal obstacles. A one-step diagonal move is then
//! allowed exactly when both orthogonal neighbours are free, the same rule
//! as the 8-connected search, so a pruned path is never worse than the path
//! it came from.
//!
//! The walk is integer-only: the next boundary crossing is found by
//! comparing `(1 + 2·ix)·dy` with `(1 + 2·iy)·dx`.

use crate::grid::{Cell, Grid};

/// Visits the supercover cells of the segment `a → b` in order, starting at
/// `a` and ending at `b`, calling `visit(x, y)` for each; stops early and
/// returns `false` as soon as `visit` returns `false`.
pub fn supercover(a: (i32, i32), b: (i32, i32), mut visit: impl FnMut(i32, i32) -> bool) -> bool {
    let (mut x, mut y) = a;
    let dx = (b.0 - a.0).unsigned_abs() as i64;
    let dy = (b.1 - a.1).unsigned_abs() as i64;
    let sx = if b.0 > a.0 { 1 } else { -1 };
    let sy = if b.1 > a.1 { 1 } else { -1 };
    if !visit(x, y) {
        return false;
    }
    let (mut ix, mut iy) = (0i64, 0i64);
    while ix < dx || iy < dy {
        let d = (1 + 2 * ix) * dy - (1 + 2 * iy) * dx;
        if d == 0 {
            // Exactly through a corner: both side cells, then the diagonal.
            if !visit(x + sx, y) || !visit(x, y + sy) {
                return false;
            }
            x += sx;
            y += sy;
            ix += 1;
            iy += 1;
        } else if d < 0 {
            x += sx;
            ix += 1;
        } else {
            y += sy;
            iy += 1;
        }
        if !visit(x, y) {
            return false;
        }
    }
    true
}

/// True when the straight line between the centres of `a` and `b` touches
/// no blocked cell (obstacle or off the map).
pub fn line_of_sight<const NW: usize>(grid: &Grid<NW>, a: Cell, b: Cell) -> bool {
    supercover(a.xy(), b.xy(), |x, y| !grid.is_blocked(x, y))
}
