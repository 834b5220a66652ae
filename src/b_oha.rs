//! B-OHA*: backtracking bidirectional boustrophedon with OHA* transit
//! (seed 000, ALGORITHMS.md §1). The step loop is shared
//! ([`crate::coverage`]); this file holds B-OHA*'s own rules.
//!
//! - **Traversal priority by aspect ratio** (§2.1): when the map's N–S
//!   extent exceeds its E–W extent the move priority is N, S, E, W (sweep
//!   columns), otherwise W, E, S, N (sweep rows), so the sweep runs along
//!   the long side and turns less. The extent is the map's (the paper's
//!   "working environment").
//! - **Local coverage** (Algorithm 2, steps 2–3): at each cell, every
//!   uncovered free neighbour (all eight, S1..S8) enters the backtracking
//!   list; the robot moves one cell to the highest-priority free uncovered
//!   4-neighbour, which leaves the list.
//! - **Pruning at a critical point** (§2.2): covered points leave the list,
//!   and so does every point with (S3 and S7 uncovered) or (S1 and S5
//!   uncovered): it sits inside an uncovered run, not at its corner.
//! - **Transit** (§2.3): multi-goal OHA* to the backtracking points, then
//!   path pruning (Algorithm 1). The digest leaves the goal range open; we
//!   take the [`MAX_GOALS`] points nearest in straight line (all of them on
//!   the paper's maps) and θ toward the nearest goal.

use crate::coverage::{uncovered, Coverage, E_, N_, S_, W_};
use crate::grid::{Cell, Grid};
use crate::search::{Algo, MAX_GOALS, NEIGHBOURS};

/// Goals per transit and the search used.
pub const TRANSIT: (usize, Algo) = (MAX_GOALS, Algo::Oha);

/// Move priority from the map's aspect ratio.
pub fn priority<const GW: usize>(grid: &Grid<GW>) -> [(i32, i32); 4] {
    if grid.height() > grid.width() {
        [N_, S_, E_, W_]
    } else {
        [W_, E_, S_, N_]
    }
}

impl<const N: usize, const NW: usize, const OPEN: usize, const LCAP: usize, const PCAP: usize>
    Coverage<N, NW, OPEN, LCAP, PCAP>
{
    /// Pushes every uncovered free 8-neighbour of the robot's cell.
    pub(crate) fn b_oha_push_neighbours<const GW: usize>(&mut self, grid: &Grid<GW>) {
        let (x, y) = self.cur.xy();
        for (dx, dy) in NEIGHBOURS {
            if uncovered(grid, x + dx, y + dy) {
                if let Some(c) = Cell::from_xy(x + dx, y + dy) {
                    self.push_point(grid, c);
                }
            }
        }
    }
}

/// True when the uncovered cell (x, y) survives seed 000's pruning rule:
/// not (N and S uncovered) and not (E and W uncovered).
pub fn is_corner<const GW: usize>(grid: &Grid<GW>, x: i32, y: i32) -> bool {
    let u = |dx: i32, dy: i32| uncovered(grid, x + dx, y + dy);
    !((u(0, -1) && u(0, 1)) || (u(1, 0) && u(-1, 0)))
}

impl<const N: usize, const NW: usize, const OPEN: usize, const LCAP: usize, const PCAP: usize>
    Coverage<N, NW, OPEN, LCAP, PCAP>
{
    /// The pruning at a critical point.
    pub(crate) fn b_oha_prune_list<const GW: usize>(&mut self, grid: &Grid<GW>) {
        self.retain(grid, |g, c| {
            let (x, y) = c.xy();
            uncovered(g, x, y) && is_corner(g, x, y)
        });
    }
}
