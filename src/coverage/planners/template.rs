//! The efficient template method (seed 002, ALGORITHMS.md §3).
//!
//! - **Templates.** TL, TD, TU, TR move left, down, up, right until the
//!   next cell is an obstacle, covered or off the map; priority TL > TD >
//!   TU > TR, and a higher template pre-empts a running one as soon as it
//!   matches. Re-choosing the highest matching template at every cell is
//!   exactly that rule, so it is the fixed move order W, S, N, E ("down"
//!   is +y, south, in our image coordinates).
//! - **Dead-zone list** (§3). Uncovered 8-neighbours are listed on arrival
//!   (as B-OHA* does); at a dead zone only the cells at a **corner or an
//!   edge** of their uncovered sub-region stay ([`is_edge`]): the seed's
//!   criterion (2). B-OHA*'s corner rule is stricter; the seed keeps edges
//!   too.
//! - **Next point** by criterion (1), the shortest straight-line distance
//!   to the dead point (the greedy `argmin`), one goal.
//! - **Transit.** The seed plans the global path and splits it at its
//!   turning points into straight sub-paths; it does not name the search.
//!   Ours is A* with the integer octile heuristic (optimal), and the path
//!   is pruned to its turning points (Algorithm 1), which is the seed's
//!   decomposition into straight sub-paths. DWA runs on those sub-paths in
//!   the mission, as in the seed.

use crate::coverage::cells::{uncovered, E_, N_, S_, W_};
use crate::coverage::list::BacktrackList;
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::Grid;
use crate::search::Algo;

/// The template method's rules: TL > TD > TU > TR, the dead-zone list
/// pruned to corners and edges, the nearest point reached by A* octile.
pub const RULES: Rules = Rules {
    priority: Priority::Fixed([W_, S_, N_, E_]),
    local: LocalMove::Priority,
    list: ListRule::NeighboursPrunedToEdges,
    transit_goals: 1,
    transit: Algo::AStarOctile,
    prune_transit: true,
};

/// True when the uncovered cell (x, y) lies at a corner or an edge of its
/// uncovered region: at least one 4-neighbour is not free and uncovered.
pub fn is_edge<const GW: usize>(grid: &Grid<GW>, x: i32, y: i32) -> bool {
    [N_, S_, E_, W_]
        .iter()
        .any(|&(dx, dy)| !uncovered(grid, x + dx, y + dy))
}

/// The pruning at a dead zone: uncovered corner and edge cells stay.
pub fn prune_list<const LCAP: usize, const NW: usize, const GW: usize>(
    list: &mut BacktrackList<LCAP, NW>,
    grid: &Grid<GW>,
) {
    list.retain(grid, |g, c| {
        let (x, y) = c.xy();
        uncovered(g, x, y) && is_edge(g, x, y)
    });
}
