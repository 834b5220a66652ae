//! Whether two neighbouring blocks of a block search
//! ([`super::WindowSearch::begin_blocks`]) really meet on the fine grid.
//!
//! A block is open when any of its cells is free, so that a doorway stays
//! open. A wall grown by the robot's radius stays closed only when it is at
//! least `2b − 1` cells thick; a thinner one leaves a free cell in the
//! blocks on both of its sides, and the block search crosses it (a 0.2 m
//! wall at 30 cm blocks: 9 blocked cells, under the 11 that close it). A
//! route's waypoints either side of such a wall are 30 cm apart, and no
//! window finds a way between them when the doorway is farther than a
//! window. [`blocks_connected`] checks a step of the block path on the
//! fine grid; the caller closes a block whose step fails and searches
//! again (lazy checking of a coarse path's edges, as lazy PRM does with
//! its roadmap's edges: only the steps of the path found are checked).

use crate::grid::Grid;

/// Largest block side checked: the two blocks' box (2b × 2b cells) fits
/// the check's 256-bit set. Larger blocks are taken as connected.
pub const MAX_CHECKED_SIDE: i32 = 8;

/// True when the free cells of block `a` reach those of block `p` (block
/// coordinates, 8-neighbours) through free cells of the box the two
/// blocks span, 4-connected (the fine searches forbid corner cutting, so
/// their reach is 4-connected reach). Blocks of side `b` over
/// [`MAX_CHECKED_SIDE`], or not neighbours, are taken as connected.
pub fn blocks_connected<const GW: usize>(
    big: &Grid<GW>,
    a: (i32, i32),
    p: (i32, i32),
    b: i32,
) -> bool {
    if !(1..=MAX_CHECKED_SIDE).contains(&b) || (a.0 - p.0).abs() > 1 || (a.1 - p.1).abs() > 1 {
        return true;
    }
    let (x0, y0) = (a.0.min(p.0) * b, a.1.min(p.1) * b);
    let (w, h) = (((a.0 - p.0).abs() + 1) * b, ((a.1 - p.1).abs() + 1) * b);
    let index = |x: i32, y: i32| ((y - y0) * w + (x - x0)) as usize;
    let in_block = |x: i32, y: i32, k: (i32, i32)| x / b == k.0 && y / b == k.1;
    let mut seen = [0u64; 4];
    let mut stack = [(0i16, 0i16); 256];
    let mut top = 0usize;
    let visit =
        |x: i32, y: i32, seen: &mut [u64; 4], stack: &mut [(i16, i16); 256], top: &mut usize| {
            let i = index(x, y);
            if let Some(word) = seen.get_mut(i / 64) {
                if *word & (1 << (i % 64)) == 0 && big.is_free(x, y) {
                    *word |= 1 << (i % 64);
                    if let Some(s) = stack.get_mut(*top) {
                        *s = (x as i16, y as i16);
                        *top += 1;
                    }
                }
            }
        };
    for y in a.1 * b..(a.1 + 1) * b {
        for x in a.0 * b..(a.0 + 1) * b {
            visit(x, y, &mut seen, &mut stack, &mut top);
        }
    }
    while top > 0 {
        top -= 1;
        let Some(&(x, y)) = stack.get(top) else {
            break;
        };
        let (x, y) = (x as i32, y as i32);
        if in_block(x, y, p) {
            return true;
        }
        for (nx, ny) in [(x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)] {
            if nx >= x0 && nx < x0 + w && ny >= y0 && ny < y0 + h {
                visit(nx, ny, &mut seen, &mut stack, &mut top);
            }
        }
    }
    false
}
