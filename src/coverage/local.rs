//! Local coverage: the next move by the planner's rule, the per-cell field
//! some rules keep, and what the list rule records on arrival (see the
//! module docs of [`super`]).

use super::planners::{b_oha, b_oha_pc, bcd, binn, mark_backtrack, regions, stc, wavefront};
use super::rules::{ListRule, LocalMove};
use super::{cells, Coverage};
use crate::grid::los::supercover;
use crate::grid::{Cell, Grid, Layer};

impl<
        const N: usize,
        const NW: usize,
        const OPEN: usize,
        const LCAP: usize,
        const PCAP: usize,
        const F: usize,
    > Coverage<N, NW, OPEN, LCAP, PCAP, F>
{
    /// The highest-priority 4-neighbour that is free and uncovered (pockets
    /// first, see [`super::planners::b_oha_pc`]; BINN's ranking, see
    /// [`super::planners::binn`]).
    pub(super) fn next_local_move<const GW: usize>(&self, grid: &Grid<GW>) -> Option<Cell> {
        match self.kind.rules().local {
            LocalMove::PocketsFirst => return b_oha_pc::next_move(grid, self.cur, &self.priority),
            LocalMove::LeastTurn => {
                return binn::next_move(grid, self.cur, self.heading(), &self.priority)
            }
            LocalMove::Wavefront => {
                return wavefront::next_move(grid, &self.field, self.cur, &self.priority)
            }
            LocalMove::SpanningTree => return stc::next_move(grid, &self.field, self.cur),
            LocalMove::CellSweep => {
                return bcd::next_move(grid, &self.field, self.cur, &self.priority)
            }
            LocalMove::Regions => {
                return regions::next_move(grid, &self.field, self.cur, self.heading())
            }
            LocalMove::Priority => {}
        }
        cells::open_moves(grid, self.cur, &self.priority)
            .next()
            .map(|(_, c)| c)
    }

    /// Marks the cells of the segment cur → to covered, takes them off
    /// the list, and sets the heading.
    pub(super) fn cover_segment<const GW: usize>(&mut self, grid: &mut Grid<GW>, to: Cell) {
        let (dx, dy) = (
            to.x as i32 - self.cur.x as i32,
            to.y as i32 - self.cur.y as i32,
        );
        if (dx, dy) != (0, 0) {
            self.heading = (dx.signum() as i8, dy.signum() as i8);
        }
        let w = grid.width() as usize;
        supercover(self.cur.xy(), to.xy(), |x, y| {
            if grid.is_free(x, y) {
                let _ = grid.set(Layer::Covered, x, y, true);
                let i = y as usize * w + x as usize;
                self.list.remove_index(i, Cell::new(x as u16, y as u16));
            }
            true
        });
    }

    /// (Re)builds the per-cell field of the planners that keep one.
    pub(super) fn build_field<const GW: usize>(&mut self, grid: &Grid<GW>) {
        match self.kind.rules().local {
            LocalMove::Wavefront => wavefront::build(grid, &mut self.field, self.origin),
            LocalMove::SpanningTree => stc::build(grid, &mut self.field, self.cur),
            LocalMove::CellSweep => bcd::build(grid, &mut self.field),
            LocalMove::Regions => regions::build(grid, &mut self.field),
            LocalMove::Priority | LocalMove::PocketsFirst | LocalMove::LeastTurn => {}
        }
    }

    /// The direction of the last move as (dx, dy) unit steps.
    pub(super) fn heading(&self) -> (i32, i32) {
        (i32::from(self.heading.0), i32::from(self.heading.1))
    }

    /// What the planner's list rule records on arrival at a cell.
    pub(super) fn on_arrive<const GW: usize>(&mut self, grid: &Grid<GW>) {
        match self.kind.rules().list {
            ListRule::NeighboursPrunedToCorners | ListRule::NeighboursPrunedToEdges => {
                b_oha::push_neighbours(&mut self.list, grid, self.cur)
            }
            ListRule::Marks => {
                let heading = self.heading();
                mark_backtrack::push_marks(&mut self.list, grid, self.cur, heading)
            }
            ListRule::RebuiltFromCovered | ListRule::RescanOnly => {}
        }
    }
}
