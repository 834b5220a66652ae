//! B-OHA*-PC: our variant of B-OHA* (work in progress: same as B-OHA*).

use crate::coverage::{nearest_k, Coverage};
use crate::grid::Grid;
use crate::search::{Algo, MAX_GOALS};

/// Goals per transit.
pub const GOALS: usize = MAX_GOALS;

/// Chooses the goals of the next transit.
pub(crate) fn choose_goals<
    const N: usize,
    const NW: usize,
    const OPEN: usize,
    const LCAP: usize,
    const PCAP: usize,
    const GW: usize,
>(
    p: &mut Coverage<N, NW, OPEN, LCAP, PCAP>,
    grid: &Grid<GW>,
) -> Algo {
    let _ = grid;
    let mut goals = [crate::grid::Cell::new(0, 0); MAX_GOALS];
    let n = nearest_k(p.list.as_slice(), p.cur, &mut goals, GOALS);
    p.set_goals(goals.get(..n).unwrap_or(&[]));
    Algo::Oha
}
