//! The artificial potential field: a local planner that walks downhill on
//! attraction to the goal plus repulsion from obstacles (Khatib, "Real-time
//! obstacle avoidance for manipulators and mobile robots", IJRR 1986; seed
//! 004's point-to-point method, ALGORITHMS.md §5).
//!
//! **What.** `U(s) = U_att + U_rep`, with `U_att = ½·η·‖s − goal‖²` and,
//! within `ρ0` of an obstacle, `U_rep = ½·k·(1/ρ − 1/ρ0)²`, ρ the distance
//! from `s` to the nearest blocked cell (cells off the map count as
//! blocked), all in cells. From the start the walk steps to the neighbour of
//! least U, on the search's graph (8-connected, no corner cutting), while
//! that U is strictly lower than here. It ends at the goal, or at a **local
//! minimum**: a cell with no lower neighbour that is not the goal. The
//! field has them wherever attraction pulls into a concave obstacle; this
//! module reports them ([`ApfEnd::LocalMinimum`]) rather than hiding them
//! behind an escape rule, since showing them is the point of the baseline.
//!
//! **Our choices** (the seed gives the formulas only): η = 1 and k = 64 per
//! cell², ρ0 = 3 cells, so that one cell from a wall the repulsion (14.2)
//! equals the attraction's step about 14 cells from the goal. The goal is
//! entered whenever it is one move away: with an obstacle next to the goal
//! the repulsion would otherwise hold the walk a cell short of it (the
//! "goal non-reachable with obstacles nearby" problem). Strict descent
//! visits no cell twice, so a walk is at most the map's cells long.
//!
//! **Integer form.** U in Q16 cell² units, `u64`: `U_att = η·d²·2^15`; ρ
//! with 16 fractional bits by an integer square root, `1/ρ` as `2^32 / ρ`
//! in Q16, and `U_rep = k·(1/ρ − 1/ρ0)² / 2^17`. The repulsion reads the
//! `(2ρ0 + 1)²` cells around a candidate: no field is stored.

use super::state::{check_goal, check_start, SearchError};
use crate::grid::{Cell, Grid};
use crate::math::cost::isqrt_u64;

/// The field's gains and reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ApfParams {
    /// η, the attraction per cell² (of ½·η·d²).
    pub eta: u32,
    /// k, the repulsion gain.
    pub k: u32,
    /// ρ0, the obstacles' reach in cells (1 to 15).
    pub rho0: u8,
}

/// Our defaults (the module's doc says why).
pub const APF_DEFAULT: ApfParams = ApfParams {
    eta: 1,
    k: 64,
    rho0: 3,
};

/// How a walk ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ApfEnd {
    /// At the goal.
    Goal,
    /// Held at a local minimum of the field (the last cell of the walk).
    LocalMinimum,
}

/// A walk down the field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ApfWalk {
    /// Where it ended.
    pub end: ApfEnd,
    /// Cells written to the path, start and last cell included.
    pub cells: usize,
    /// The last cell: the goal, or the local minimum.
    pub at: Cell,
}

/// Walks down the field from `start` toward `goal`, writing the cells into
/// `out`.
pub fn descend<const GW: usize>(
    grid: &Grid<GW>,
    start: Cell,
    goal: Cell,
    p: ApfParams,
    out: &mut [Cell],
) -> Result<ApfWalk, SearchError> {
    check_start(grid, start)?;
    check_goal(grid, goal)?;
    let mut at = start;
    let mut here = potential(grid, at, goal, p);
    let mut n = 0usize;
    loop {
        *out.get_mut(n).ok_or(SearchError::PathBufferTooSmall)? = at;
        n += 1;
        if at == goal {
            return Ok(ApfWalk {
                end: ApfEnd::Goal,
                cells: n,
                at,
            });
        }
        match downhill(grid, at, goal, p, here) {
            Some((next, u)) => (at, here) = (next, u),
            None => {
                return Ok(ApfWalk {
                    end: ApfEnd::LocalMinimum,
                    cells: n,
                    at,
                })
            }
        }
    }
}

/// The goal when it is one move from `at`, else the neighbour of least U
/// if that is below `here`.
fn downhill<const GW: usize>(
    grid: &Grid<GW>,
    at: Cell,
    goal: Cell,
    p: ApfParams,
    here: u64,
) -> Option<(Cell, u64)> {
    let (x, y) = at.xy();
    let mut moves = grid.moves(x, y);
    let mut best: Option<(Cell, u64)> = None;
    while moves != 0 {
        let k = moves.trailing_zeros() as usize;
        moves &= moves - 1;
        let (dx, dy) = super::NEIGHBOURS.get(k).copied().unwrap_or((0, 0));
        let next = Cell::from_xy(x + dx, y + dy)?;
        if next == goal {
            return Some((goal, 0));
        }
        let u = potential(grid, next, goal, p);
        if u < here && best.is_none_or(|(_, b)| u < b) {
            best = Some((next, u));
        }
    }
    best
}

/// U(s) in Q16 cell² units.
pub fn potential<const GW: usize>(grid: &Grid<GW>, s: Cell, goal: Cell, p: ApfParams) -> u64 {
    let (dx, dy) = (s.x as i64 - goal.x as i64, s.y as i64 - goal.y as i64);
    let d2 = (dx * dx + dy * dy) as u64;
    let attract = (p.eta as u64 * d2) << 15;
    attract.saturating_add(repulsion(grid, s, p))
}

/// ½·k·(1/ρ − 1/ρ0)² in Q16, 0 beyond ρ0.
fn repulsion<const GW: usize>(grid: &Grid<GW>, s: Cell, p: ApfParams) -> u64 {
    let r0 = p.rho0.clamp(1, 15) as i32;
    let Some(rho2) = nearest_blocked2(grid, s, r0) else {
        return 0;
    };
    let inv = |r2: u64| (1u64 << 32) / isqrt_u64(r2 << 32).max(1);
    let diff = inv(rho2).saturating_sub(inv((r0 * r0) as u64));
    (p.k as u64).saturating_mul(diff * diff) >> 17
}

/// The squared distance to the nearest blocked or off-map cell within
/// `r0` (by ρ², so within the disc), if any.
fn nearest_blocked2<const GW: usize>(grid: &Grid<GW>, s: Cell, r0: i32) -> Option<u64> {
    let (x, y) = s.xy();
    let mut best: Option<u64> = None;
    for dy in -r0..=r0 {
        for dx in -r0..=r0 {
            let d2 = (dx * dx + dy * dy) as u64;
            if d2 == 0 || d2 > (r0 * r0) as u64 || best.is_some_and(|b| d2 >= b) {
                continue;
            }
            if grid.is_blocked(x + dx, y + dy) {
                best = Some(d2);
            }
        }
    }
    best
}
