//! Theta* (Nash, Daniel, Koenig and Felner 2007): the any-angle baseline
//! seed 000 compares OHA* against (Table 1), and the transit search of
//! B-Theta*.
//!
//! Theta* is A* in which a neighbour `n` of the expanded cell `s` may take
//! `s`'s own parent as its parent when the two see each other ("path 2"):
//! g(n) = g(parent(s)) + |parent(s) − n|. Line of sight is the project's
//! conservative supercover test ([`crate::grid::los`]), so an any-angle segment
//! never clips an obstacle corner. Costs are Euclidean in cost units; the
//! heuristic is the Euclidean distance to the nearest goal, as for A*.

use super::state::SearchState;
use crate::grid::los::supercover;
use crate::grid::Grid;
use crate::math::cost::euclid;

/// The parent update for neighbour `(nx, ny)` of expanded cell `i` (whose
/// cost is `gs`): returns the candidate cost and parent index.
pub(crate) fn relax<const N: usize, const NW: usize, const OPEN: usize, const GW: usize>(
    state: &SearchState<N, NW, OPEN>,
    grid: &Grid<GW>,
    i: usize,
    gs: u32,
    (nx, ny): (i32, i32),
    step: u32,
) -> (u32, u32) {
    let p = state.parent_at(i);
    if p != i {
        let w = (grid.width() as usize).max(1);
        let (px, py) = ((p % w) as i32, (p / w) as i32);
        if supercover((px, py), (nx, ny), |x, y| !grid.is_blocked(x, y)) {
            let cand = state.g_at(p).saturating_add(euclid(nx - px, ny - py));
            return (cand, p as u32);
        }
    }
    (gs.saturating_add(step), i as u32)
}
