//! The emulated run's independent checker: a small Dijkstra of its own
//! (its own binary heap, no code shared with the core's searches) and a
//! step-by-step path check.

use super::common::fail;
use robovac::capacity::BENCH_CELLS;
use robovac::grid::Grid;
use robovac::math::cost::{COST_DIAGONAL, COST_PER_CELL};
use robovac::Cell;

/// Oracle heap entries (lazy deletion; a full heap fails the run loudly).
const HEAP_CAP: usize = 1024;

pub struct Oracle {
    dist: [u32; BENCH_CELLS],
    heap: [(u32, u32); HEAP_CAP],
}

impl Oracle {
    pub const fn new() -> Self {
        Self {
            dist: [0; BENCH_CELLS],
            heap: [(0, 0); HEAP_CAP],
        }
    }

    /// Exact optimal octile cost (same integer units) from s to t.
    pub fn cost<const NW: usize>(&mut self, g: &Grid<NW>, s: Cell, t: Cell) -> Option<u32> {
        let w = g.width() as i32;
        let n = g.cells();
        for d in self.dist.iter_mut().take(n) {
            *d = u32::MAX;
        }
        let free = |x: i32, y: i32| g.contains(x, y) && !g.is_blocked(x, y);
        let idx = |x: i32, y: i32| (y * w + x) as usize;
        let mut len = 0usize;
        self.dist[idx(s.x as i32, s.y as i32)] = 0;
        self.push(&mut len, 0, idx(s.x as i32, s.y as i32) as u32);
        while let Some((d, i)) = self.pop(&mut len) {
            if d > self.dist[i as usize] {
                continue;
            }
            let (x, y) = ((i as i32) % w, (i as i32) / w);
            if (x, y) == (t.x as i32, t.y as i32) {
                return Some(d);
            }
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if (dx, dy) == (0, 0) || !free(x + dx, y + dy) {
                        continue;
                    }
                    let diag = dx != 0 && dy != 0;
                    if diag && !(free(x + dx, y) && free(x, y + dy)) {
                        continue;
                    }
                    let nd = d + if diag { COST_DIAGONAL } else { COST_PER_CELL };
                    let j = idx(x + dx, y + dy);
                    if nd < self.dist[j] {
                        self.dist[j] = nd;
                        if !self.push(&mut len, nd, j as u32) {
                            fail("oracle heap full");
                        }
                    }
                }
            }
        }
        None
    }

    fn push(&mut self, len: &mut usize, d: u32, i: u32) -> bool {
        if *len >= HEAP_CAP {
            return false;
        }
        let mut k = *len;
        *len += 1;
        while k > 0 && self.heap[(k - 1) / 2].0 > d {
            self.heap[k] = self.heap[(k - 1) / 2];
            k = (k - 1) / 2;
        }
        self.heap[k] = (d, i);
        true
    }

    fn pop(&mut self, len: &mut usize) -> Option<(u32, u32)> {
        if *len == 0 {
            return None;
        }
        let top = self.heap[0];
        *len -= 1;
        let last = self.heap[*len];
        let mut k = 0;
        loop {
            let mut c = 2 * k + 1;
            if c >= *len {
                break;
            }
            if c + 1 < *len && self.heap[c + 1].0 < self.heap[c].0 {
                c += 1;
            }
            if self.heap[c].0 < last.0 {
                self.heap[k] = self.heap[c];
                k = c;
            } else {
                break;
            }
        }
        self.heap[k] = last;
        Some(top)
    }
}

/// Path check: 8-connected steps on free cells, no corner cutting.
/// Returns the octile cost in integer units.
pub fn check_steps<const NW: usize>(g: &Grid<NW>, p: &[Cell]) -> Option<u32> {
    let mut cost = 0u32;
    if p.iter().any(|c| g.is_blocked(c.x as i32, c.y as i32)) {
        return None;
    }
    for w in p.windows(2) {
        let (dx, dy) = (w[1].x as i32 - w[0].x as i32, w[1].y as i32 - w[0].y as i32);
        if dx.abs() > 1 || dy.abs() > 1 || (dx, dy) == (0, 0) {
            return None;
        }
        if dx != 0 && dy != 0 {
            if g.is_blocked(w[0].x as i32 + dx, w[0].y as i32)
                || g.is_blocked(w[0].x as i32, w[0].y as i32 + dy)
            {
                return None;
            }
            cost += COST_DIAGONAL;
        } else {
            cost += COST_PER_CELL;
        }
    }
    Some(cost)
}
