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

use super::cover::ALL_CELLS;
use crate::grid::rooms::{self, label_at, RoomParams, NONE};
use crate::grid::Cell;
use crate::math::bits::Bits;
use crate::robot::lidar_map::CellBox;

/// Which rooms there are and which are open. How many have been entered
/// is counted once, in [`super::Counters::rooms_entered`].
#[derive(Clone, Default)]
pub(super) struct RoomTour {
    /// Rooms (0 or 1: no tour, the whole home at once).
    count: u8,
    /// Open rooms, a bit each (ids 1..=126).
    open: Bits<4>,
}

impl RoomTour {
    /// No rooms.
    pub(super) const fn new() -> Self {
        Self {
            count: 0,
            open: Bits::new(),
        }
    }

    /// A tour is under way (more than one room).
    fn on(&self) -> bool {
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
    }

    /// Opens room `id`, counting it when a tour is under way.
    fn open_room(&mut self, id: u8) {
        if self.m.rooms.open(id) && self.m.rooms.on() {
            self.m.counters.rooms_entered += 1;
        }
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
        let at = self.p.planner.position();
        if self.p.planner.start_keeping(self.p.coarse, at).is_err() {
            return false;
        }
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
