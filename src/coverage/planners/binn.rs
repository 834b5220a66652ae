//! The bio-inspired neural network (BINN) coverage of seed 004
//! (ALGORITHMS.md §5; Yang and Luo, IEEE SMC-B 2004).
//!
//! Each cell is a neuron with the shunting dynamics
//! dx/dt = −A·x + (B − x)·([I]⁺ + Σ w·[x_k]⁺) − (D + x)·[I]⁻, external input
//! I = +E on uncovered cells, −E on obstacles and 0 on covered ones, and
//! lateral weights w = μ/d to the eight neighbours. The robot moves to the
//! neighbour j that maximises x_j + c·(1 − Δθ_j/π), Δθ_j being the turn.
//!
//! **What we compute, and why it is the same choice.** We do not integrate
//! the network; we rank the neighbours by its steady state. With the
//! paper's E = 100, A = 10, B = 1, μ = 0.7, an uncovered cell's steady
//! activity B·(E + S)/(A + E + S) lies between 0.909 (no lateral input S)
//! and 0.913 (eight uncovered neighbours), a covered cell's S/(A + S) below
//! 0.31 and an obstacle's is negative. So an uncovered 4-neighbour always
//! wins over a covered one, and among uncovered ones the turn term (steps
//! of 0.5·c) decides for any c above 0.01, the lateral input S breaking its
//! ties ([`activity_q8`]); the fixed order N, S, E, W breaks the rest.
//!
//! **Our decisions.**
//! - Moves go to 4-neighbours: a cell is one cleaning width, and a
//!   diagonal cover move would leave the corners between lanes to a later
//!   transit.
//! - **Dead ends.** When no neighbour is uncovered, the network's activity
//!   still rises toward the uncovered cells, spread from them through the
//!   covered ones, and the robot climbs it to the nearest uncovered region
//!   by path distance. We take that walk as a transit: the shared rescan
//!   lists every uncovered region's corner cells, and a multi-goal A* with
//!   the octile heuristic reaches the one nearest by path cost, pruned.

use crate::coverage::cells::{best_move, open_moves, uncovered, E_, N_, S_, W_};
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::{Cell, Grid};
use crate::search::{Algo, MAX_GOALS, NEIGHBOURS};

/// BINN's rules: the least-turn, most-active neighbour; nothing listed
/// while sweeping; multi-goal A* octile to the nearest uncovered region.
pub const RULES: Rules = Rules {
    priority: Priority::Fixed([N_, S_, E_, W_]),
    local: LocalMove::LeastTurn,
    list: ListRule::RescanOnly,
    transit_goals: MAX_GOALS,
    transit: Algo::AStarOctile,
    prune_transit: true,
};

/// Lateral weight μ/d to an orthogonal neighbour, ×256 (μ = 0.7).
const W_ORTHO_Q8: u32 = 179;
/// Lateral weight μ/d to a diagonal neighbour, ×256 (0.7/√2).
const W_DIAG_Q8: u32 = 127;

/// The lateral input S of the cell (x, y), ×256: the weights of its
/// uncovered neighbours (their activity ≈ 0.91 is the same for all, so it
/// is left out of the ranking).
pub fn activity_q8<const GW: usize>(grid: &Grid<GW>, x: i32, y: i32) -> u32 {
    NEIGHBOURS
        .iter()
        .filter(|&&(dx, dy)| uncovered(grid, x + dx, y + dy))
        .map(|&(dx, dy)| {
            if dx != 0 && dy != 0 {
                W_DIAG_Q8
            } else {
                W_ORTHO_Q8
            }
        })
        .sum()
}

/// The turn term's rank: 2 straight on (or no heading yet), 1 for a
/// quarter turn, 0 for turning back (y = 1, 0.5, 0).
fn turn_rank(heading: (i32, i32), dir: (i32, i32)) -> u32 {
    if heading == (0, 0) || heading == dir {
        2
    } else if heading == (-dir.0, -dir.1) {
        0
    } else {
        1
    }
}

/// The next local move: the uncovered 4-neighbour of highest rank (turn
/// term first, lateral input next, `priority` order last); `None` at a
/// dead end.
pub fn next_move<const GW: usize>(
    grid: &Grid<GW>,
    cur: Cell,
    heading: (i32, i32),
    priority: &[(i32, i32); 4],
) -> Option<Cell> {
    best_move(open_moves(grid, cur, priority), |dir, n| {
        let (nx, ny) = n.xy();
        turn_rank(heading, dir) * 4096 + activity_q8(grid, nx, ny)
    })
}
