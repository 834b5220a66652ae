//! Keeping the backtracking list honest between transits: stale points
//! dropped, unreachable goals abandoned, the completeness rescan (see the
//! module docs of [`super`]), and the goals of the next transit.

use super::cells::{self, nearest_k, uncovered};
use super::planners::{ba_star, bcd, mark_backtrack, regions};
use super::rules::{ListRule, LocalMove};
use super::Coverage;
use crate::grid::{Cell, Grid, Layer};
use crate::search::Algo;

impl<
        const N: usize,
        const NW: usize,
        const OPEN: usize,
        const LCAP: usize,
        const PCAP: usize,
        const F: usize,
    > Coverage<N, NW, OPEN, LCAP, PCAP, F>
{
    /// Drops points that became obstacles or are no longer worth visiting
    /// under the planner's own rule.
    pub(super) fn drop_stale<const GW: usize>(&mut self, grid: &mut Grid<GW>) {
        // A point where the planner already stands (put back by a caller
        // that un-covered it) is covered by standing there.
        let (cx, cy) = self.cur.xy();
        if uncovered(grid, cx, cy) && self.list.as_slice().contains(&self.cur) {
            let _ = grid.set(Layer::Covered, cx, cy, true);
        }
        let rule = self.kind.rules().list;
        self.list.retain(grid, |g, c| {
            let (x, y) = c.xy();
            !g.is_blocked(x, y)
                && if rule.points_uncovered() {
                    // B-OHA*'s points (and all but BA*'s) are uncovered cells.
                    !g.get(Layer::Covered, x, y)
                } else {
                    // BA* points are covered cells with uncovered neighbours,
                    // or (fallback) uncovered cells.
                    !g.get(Layer::Covered, x, y) || ba_star::b(g, x, y) > 0
                }
        });
    }

    pub(super) fn abandon<const GW: usize>(&mut self, grid: &Grid<GW>, c: Cell) {
        if self.list.abandon(grid, c) {
            self.stats.abandoned_goals += 1;
        }
    }

    /// The completeness fallback: refills the list with the uncovered
    /// corner cells of every uncovered region (see the module docs); for
    /// BCD, of every decomposition cell's uncovered part.
    pub(super) fn rescan<const GW: usize>(&mut self, grid: &Grid<GW>) {
        let (w, h) = (grid.width() as i32, grid.height() as i32);
        let by_cell = matches!(
            self.kind.rules().local,
            LocalMove::CellSweep | LocalMove::Regions
        );
        let mut found = false;
        for y in 0..h {
            for x in 0..w {
                let corner = if by_cell {
                    bcd::is_cell_corner(grid, &self.field, x, y)
                } else {
                    cells::is_corner(grid, x, y)
                };
                if !uncovered(grid, x, y) || !corner {
                    continue;
                }
                let Some(i) = grid.index(x, y) else { continue };
                if self.list.is_abandoned(i) {
                    continue;
                }
                found = true;
                if !self.list.push(grid, Cell::new(x as u16, y as u16)) {
                    if found {
                        self.stats.rescans_with_points += 1;
                    }
                    return; // full: the next rescan finds the rest
                }
            }
        }
        if found {
            self.stats.rescans_with_points += 1;
        }
    }

    /// Fills `self.goals` for the next transit and returns the search:
    /// the points nearest in straight line, or seed 001's north and south
    /// points first ([`mark_backtrack::choose`]).
    pub(super) fn choose_goals<const GW: usize>(&mut self, grid: &Grid<GW>) -> Algo {
        let rules = self.kind.rules();
        let ranked = match (rules.list, rules.local) {
            (ListRule::Marks, _) => {
                Some(mark_backtrack::choose(self.list.as_slice(), grid, self.cur))
            }
            (_, LocalMove::CellSweep) => {
                let here = bcd::label(grid, &self.field, self.cur.x as i32, self.cur.y as i32);
                let rank = |c: Cell| {
                    u32::from(bcd::label(grid, &self.field, c.x as i32, c.y as i32) != here)
                };
                Some(cells::nearest_of_best_rank(
                    self.list.as_slice(),
                    self.cur,
                    rank,
                ))
            }
            (_, LocalMove::Regions) => {
                let here = bcd::label(grid, &self.field, self.cur.x as i32, self.cur.y as i32);
                let rank = |c: Cell| {
                    let other = bcd::label(grid, &self.field, c.x as i32, c.y as i32) != here;
                    u32::from(other) * 8 + regions::ccw_rank(grid, self.cur, c)
                };
                Some(cells::nearest_of_best_rank(
                    self.list.as_slice(),
                    self.cur,
                    rank,
                ))
            }
            _ => None,
        };
        if let Some(goal) = ranked {
            self.goal_count = 0;
            if let (Some(g), Some(slot)) = (goal, self.goals.first_mut()) {
                *slot = g;
                self.goal_count = 1;
            }
            return rules.transit;
        }
        let k = rules.transit_goals;
        self.goal_count = nearest_k(self.list.as_slice(), self.cur, &mut self.goals, k);
        rules.transit
    }
}
