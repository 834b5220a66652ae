//! Path pruning, seed 000 Algorithm 1 (greedy line of sight).
//!
//! From the current point S_k, find the farthest later point S_i
//! (i = n, n−1, …, k+1) with a clear line from S_k, keep it, set k = i,
//! and stop at S_n. The line test is the conservative supercover
//! ([`crate::grid::los`]), so a pruned path never enters an obstacle nor cuts a
//! corner, and it is never longer than the path it came from.

use crate::grid::los::line_of_sight;
use crate::grid::{Cell, Grid};

/// Prunes `path` in place; returns the new length (the kept points are at
/// the front). A path of 0, 1 or 2 points is returned as it is.
pub fn prune<const NW: usize>(grid: &Grid<NW>, path: &mut [Cell]) -> usize {
    let n = path.len();
    if n <= 2 {
        return n;
    }
    let mut k = 0usize; // index of S_k in the input
    let mut m = 1usize; // points written so far (path[0] stays)
    while k < n - 1 {
        let Some(&sk) = path.get(k) else { break };
        // Farthest visible point; adjacent points of a search path are
        // always mutually visible, so fall back to k + 1 if even that fails
        // (a grid that changed under the path): the path is then kept as is.
        let mut next = k + 1;
        let mut i = n - 1;
        while i > k + 1 {
            if let Some(&si) = path.get(i) {
                if line_of_sight(grid, sk, si) {
                    next = i;
                    break;
                }
            }
            i -= 1;
        }
        let p = path.get(next).copied().unwrap_or(sk);
        if let Some(slot) = path.get_mut(m) {
            *slot = p;
        }
        m += 1;
        k = next;
    }
    m
}
