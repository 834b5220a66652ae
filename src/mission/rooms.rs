//! Room by room (issue 12): a known-mode mission splits its planning
//! cells into rooms when it begins ([`crate::grid::rooms`]) and cleans
//! one room completely before the next, so the backtracking list never
//! sends the robot across the home for one forgotten cell.
//!
//! **How (our design).** Rooms not yet opened are *fenced*: their
//! planning cells read as blocked, so the planner's lanes stop at their
//! doorways and its list never holds their cells. When the planner has
//! nothing left, the next room is opened (its cells derived again from
//! the map) and the planner starts again from where the robot stands,
//! keeping what is clean. Rooms already cleaned stay open, so transits
//! may cross them.
//!
//! **The tour (our rule).** The first room is the dock's. The next is,
//! of the rooms next to an open one, the one with a cell nearest the
//! robot: a greedy tour from the dock that never jumps over a room. A room
//! next to no open one (cut off on the map) is opened last, nearest
//! first. In unknown mode the map grows as the robot goes, so there are
//! no rooms and the planner runs over the whole home as before.
//!
//! **Edges per room (issue 12: lanes, then the room's edges).** When a
//! room's lanes are done, the edge pass runs over the open rooms only:
//! the fine cells of fenced rooms are marked covered first
//! ([`Exec::scope_edges`]), so the pass takes them for swept and never
//! goes there; when it is done the marks are lifted and the next room
//! opens. The edge pass of the rooms already edged left their contour
//! cells visited, so each pass runs along the new room's edges.

use super::cover::ALL_CELLS;
use crate::grid::rooms::{self, label_at, RoomParams, NONE};
use crate::grid::Cell;
use crate::grid::Layer;
use crate::math::bits::Bits;
use crate::nav::cspace;
use crate::nav::geometry::along;
use crate::robot::lidar_map::CellBox;
use crate::robot::lidar_map::CellState;

/// What a lane blocked by a thin wall costs in lanes when the sweep
/// direction of a room is chosen ([`rooms::lanes`]): the detour around
/// the wall, through a door, is a few turns and metres (our choice,
/// measured on the flats and the real homes).
const WALL_LANES: u32 = 5;

/// Which rooms there are and which are open. How many have been entered
/// is counted once, in [`super::Counters::rooms_entered`].
#[derive(Clone, Default)]
pub(super) struct RoomTour {
    /// Rooms (0 or 1: no tour, the whole home at once).
    count: u8,
    /// Open rooms, a bit each (ids 1..=126).
    open: Bits<4>,
    /// A room opened since the last edge pass: its edges are due.
    pub(super) edge_due: bool,
}

impl RoomTour {
    /// No rooms.
    pub(super) const fn new() -> Self {
        Self {
            count: 0,
            open: Bits::new(),
            edge_due: false,
        }
    }

    /// A tour is under way (more than one room).
    pub(super) fn on(&self) -> bool {
        self.count > 1
    }

    fn is_open(&self, id: u8) -> bool {
        self.open.get(id as usize)
    }

    /// Opens room `id`; true when it was not open before.
    fn open(&mut self, id: u8) -> bool {
        let was = self.is_open(id);
        self.open.put(id as usize, true);
        !was
    }

    /// Planning cell (gx, gy) lies outside the edge pass's scope: its room
    /// is fenced, or, blocked itself (next to a wall), one of its eight
    /// neighbours' rooms is and none is open ([`Exec::scope_edges`]).
    pub(super) fn out_of_scope<const NW: usize>(
        &self,
        g: &crate::grid::Grid<NW>,
        labels: &[u8],
        gx: i32,
        gy: i32,
    ) -> bool {
        let id = label_at(g, labels, gx, gy);
        if id != NONE {
            return self.fenced(id);
        }
        let (mut fenced, mut open) = (false, false);
        for (dx, dy) in crate::search::NEIGHBOURS {
            let n = label_at(g, labels, gx + dx, gy + dy);
            fenced |= self.fenced(n);
            open |= n != NONE && self.is_open(n);
        }
        fenced && !open
    }

    /// A planning cell's room is fenced (not yet open; nothing is
    /// fenced before the first room opens).
    fn fenced(&self, id: u8) -> bool {
        self.on()
            && id != NONE
            && !self.is_open(id)
            && self.open.count_prefix(Bits::<4>::CAPACITY) > 0
    }
}

sized_impl!([] {
    /// When a known-mode mission begins: splits the planning cells into
    /// rooms (the fine path buffer lends the wavefront queue). Without a
    /// labels buffer of the grid's size, or on a queue overflow, there is
    /// no tour.
    pub(super) fn split_rooms(&mut self) {
        self.m.rooms = RoomTour::new();
        let g = &*self.p.coarse;
        if self.p.rooms.len() < g.cells() {
            return;
        }
        if let Ok(r) = rooms::segment(g, self.p.rooms, self.p.path, RoomParams::DEFAULT) {
            self.m.rooms.count = r.count;
        }
    }

    /// Opens the room of the planner's start cell.
    pub(super) fn enter_first_room(&mut self, start: Cell) {
        let (x, y) = start.xy();
        let id = label_at(self.p.coarse, self.p.rooms, x, y);
        if id == NONE {
            // The dock's cell is in no room: no tour.
            self.m.rooms.count = 0;
        }
        self.open_room(id);
        self.fence(ALL_CELLS);
        self.align_lanes(id);
    }

    /// Lanes along the room's long axis (issue 12): with a tour, the
    /// planner sweeps room `id` the way that takes fewer lanes
    /// ([`rooms::lanes`]), not the whole home's. Two neighbouring planning
    /// cells are joined unless the map holds a wall on the line between
    /// their centres: a wall thinner than a cell leaves the cells on both
    /// sides free, and lanes across it would each need a detour (measured
    /// on the home flat, whose east rooms share one thin wall: columns
    /// across it cost 300 s).
    fn align_lanes(&mut self, id: u8) {
        if !self.m.rooms.on() {
            return;
        }
        let (map, cell) = (&*self.p.map, self.m.cfg.plan_cell_mm);
        let res = map.res_mm().max(1) as i64;
        let centre = |(x, y): (i32, i32)| cspace::coarse_centre_mm(map, cell, x, y);
        let joined = |a, b| {
            along(centre(a), centre(b), res, |x, y| {
                let (cx, cy) = map.cell_of(x as i32, y as i32);
                map.state(cx, cy) != CellState::Occupied
            })
        };
        let (rows, cols) = rooms::lanes(self.p.coarse, self.p.rooms, id, WALL_LANES, joined);
        self.p.planner.sweep_columns(cols < rows);
    }

    /// Opens room `id`, counting it when a tour is under way.
    fn open_room(&mut self, id: u8) {
        if self.m.rooms.open(id) && self.m.rooms.on() {
            self.m.counters.rooms_entered += 1;
            self.m.rooms.edge_due = true;
        }
    }

    /// Marks (`on`) or clears the fine grid's covered layer over the rooms
    /// not yet open, so the edge pass keeps to the open ones. A fine cell
    /// belongs to its planning cell's room; in a blocked planning cell
    /// (next to a wall, where the contours run), to the rooms of its
    /// eight neighbours: fenced when one is and none is open.
    pub(super) fn scope_edges(&mut self, on: bool) {
        if !self.m.rooms.on() {
            return;
        }
        let (g, labels, fine) = (&*self.p.coarse, &*self.p.rooms, &mut *self.p.fine);
        let (map, tour) = (&*self.p.map, &self.m.rooms);
        let (c, res) = (self.m.cfg.plan_cell_mm as i64, map.res_mm().max(1) as i64);
        // Fine cells whose centre lies in [lo, hi) mm.
        let span = |lo: i64, hi: i64| ((lo - res / 2 + res - 1).div_euclid(res), (hi - 1 - res / 2).div_euclid(res));
        for i in 0..g.cells() {
            let (gx, gy) = g.cell_at(i).xy();
            if !tour.out_of_scope(g, labels, gx, gy) {
                continue;
            }
            let (x0, x1) = span(gx as i64 * c, (gx as i64 + 1) * c);
            let (y0, y1) = span(gy as i64 * c, (gy as i64 + 1) * c);
            for cy in y0..=y1 {
                for cx in x0..=x1 {
                    let _ = fine.set(Layer::Covered, cx as i32, cy as i32, on);
                }
            }
        }
    }

    /// The edge pass over the open rooms is done: lifts its scope and
    /// opens the next room, whose lanes start where the robot stands (at
    /// `from`, world mm) when that planning cell is free. False without a
    /// tour or with every room open.
    pub(super) fn next_room_after_edges(&mut self, from: (i32, i32)) -> bool {
        if !self.m.rooms.on() {
            return false;
        }
        self.m.rooms.edge_due = false;
        self.scope_edges(false);
        self.next_room_from(Some(from))
    }

    /// The planning cell holding world point `from` when it is free now,
    /// else (none given, or blocked: a mark, a person mapped there) the
    /// planner's own position: where the planner starts again after an
    /// edge pass.
    pub(super) fn standing_cell(&self, from: Option<(i32, i32)>) -> Cell {
        let g = &*self.p.coarse;
        from.and_then(|(x, y)| {
            let (gx, gy) = cspace::coarse_of(self.p.map, self.m.cfg.plan_cell_mm, x, y);
            Cell::from_xy(gx, gy)
        })
        .filter(|c| g.is_free(c.x as i32, c.y as i32))
        .unwrap_or(self.p.planner.position())
    }

    /// Blocks the planning cells in `cells` (inclusive, clipped to the
    /// grid) of rooms not yet open.
    pub(super) fn fence(&mut self, cells: CellBox) {
        if !self.m.rooms.on() {
            return;
        }
        let g = &mut *self.p.coarse;
        let (w, h) = (g.width() as i32, g.height() as i32);
        for y in cells.1.max(0)..=cells.3.min(h - 1) {
            for x in cells.0.max(0)..=cells.2.min(w - 1) {
                if self.m.rooms.fenced(label_at(g, self.p.rooms, x, y)) {
                    let _ = g.set_obstacle(x, y, true);
                }
            }
        }
    }

    /// The open rooms are clean: opens the next room of the tour and
    /// starts the planner again where it stands. False when every room
    /// is open (the cleaning is done).
    pub(super) fn next_room(&mut self) -> bool {
        self.next_room_from(None)
    }

    /// [`Self::next_room`], the planner starting where the robot stands
    /// at `from` when that cell is free once the room is open
    /// ([`Self::standing_cell`]).
    fn next_room_from(&mut self, from: Option<(i32, i32)>) -> bool {
        if !self.m.rooms.on() {
            return false;
        }
        let Some(id) = self.pick_next_room() else {
            return false;
        };
        self.open_room(id);
        // Derive the room's cells again from the map, then fence the rest.
        let g = &*self.p.coarse;
        for i in 0..g.cells() {
            if self.p.rooms.get(i) == Some(&id) {
                let (x, y) = g.cell_at(i).xy();
                self.m.note_coarse_set(x, y);
            }
        }
        self.m.map_dirty = true;
        self.refresh_coarse();
        let at = self.standing_cell(from);
        if self.p.planner.start_keeping(self.p.coarse, at).is_err() {
            return false;
        }
        self.align_lanes(id);
        self.m.planner_done = false;
        self.m.abandon_rounds = 0;
        true
    }

    /// The tour's next room: of the rooms next to an open one, the one
    /// with a cell nearest the planner; else the nearest fenced room.
    fn pick_next_room(&self) -> Option<u8> {
        let g = &*self.p.coarse;
        let labels = &*self.p.rooms;
        let (px, py) = self.p.planner.position().xy();
        // (next to an open room, squared distance, id): the least wins.
        let mut best: Option<(bool, i64, u8)> = None;
        for i in 0..g.cells() {
            let id = labels.get(i).copied().unwrap_or(NONE);
            if !self.m.rooms.fenced(id) {
                continue;
            }
            let (x, y) = g.cell_at(i).xy();
            let touches = [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|&(dx, dy)| {
                let n = label_at(g, labels, x + dx, y + dy);
                n != NONE && self.m.rooms.is_open(n)
            });
            let d = ((x - px) as i64).pow(2) + ((y - py) as i64).pow(2);
            let key = (!touches, d, id);
            if best.is_none_or(|b| key < b) {
                best = Some(key);
            }
        }
        best.map(|(_, _, id)| id)
    }
});
