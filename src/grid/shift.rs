//! Moving a grid's contents by whole cells, in place: what a scrolling map
//! needs (issue 11 §3, [`crate::robot::lidar_map::EvidenceMap::shift`] and
//! the planning grid's covered layer). Written once for every grid kind:
//! the visiting order that reads each source cell before it is
//! overwritten.

/// Visits every cell of a `width × height` grid once as a destination of
/// a shift by (`dx`, `dy`) cells (contents move `dx` columns right and
/// `dy` rows down), in an order that reads every source before it is
/// written: `f(dst, Some(src))` where the source lies on the grid,
/// `f(dst, None)` for the strip the shift leaves behind (to be cleared).
/// Indices are row-major (`y × width + x`). Shifts of a whole side or
/// more visit every cell with `None`.
pub fn for_shift(
    width: u32,
    height: u32,
    dx: i32,
    dy: i32,
    mut f: impl FnMut(usize, Option<usize>),
) {
    let (w, h) = (width as i64, height as i64);
    let (dx, dy) = (dx as i64, dy as i64);
    for j in 0..h {
        // Moving down, the bottom row is written first; else the top.
        let y = if dy > 0 { h - 1 - j } else { j };
        for i in 0..w {
            let x = if dx > 0 { w - 1 - i } else { i };
            let (sx, sy) = (x - dx, y - dy);
            let src = (sx >= 0 && sy >= 0 && sx < w && sy < h).then(|| (sy * w + sx) as usize);
            f((y * w + x) as usize, src);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shifting a numbered 5 × 4 grid in place matches the shift computed
    /// into a separate copy, for every direction and size (whole-side
    /// shifts included).
    #[test]
    fn in_place_equals_copy() {
        let (w, h) = (5u32, 4u32);
        for dy in -4..=4 {
            for dx in -5..=5 {
                let orig: [i32; 20] = core::array::from_fn(|i| i as i32 + 1);
                let mut a = orig;
                for_shift(w, h, dx, dy, |d, s| {
                    let v = s.and_then(|s| a.get(s).copied()).unwrap_or(0);
                    if let Some(slot) = a.get_mut(d) {
                        *slot = v;
                    }
                });
                for y in 0..h as i32 {
                    for x in 0..w as i32 {
                        let (sx, sy) = (x - dx, y - dy);
                        let inside = (0..w as i32).contains(&sx) && (0..h as i32).contains(&sy);
                        let at = |x: i32, y: i32| (y * w as i32 + x) as usize;
                        let want = if inside {
                            orig.get(at(sx, sy)).copied()
                        } else {
                            Some(0)
                        };
                        assert_eq!(a.get(at(x, y)).copied(), want, "{dx},{dy} at {x},{y}");
                    }
                }
            }
        }
    }
}
