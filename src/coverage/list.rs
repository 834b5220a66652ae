//! The bounded backtracking list (seed 000 Algorithm 2): points in a
//! `heapless::Vec` of capacity `LCAP`, membership and given-up goals in
//! two bitsets, so a point is never listed twice nor retried once proved
//! unreachable. A leaf of the coverage layer: uses `grid` and `math`.
//!
//! **Overflow policy.** A point that does not fit is dropped and counted
//! ([`BacktrackList::overflows`]); the planner's rescan finds it again
//! when the list runs empty (see the module docs of [`super`]).
//!
//! Removal swaps the last point into the hole (`swap_remove`), so the
//! order the planners see, and hence their plans, is the one of the
//! original hand-written list.

use crate::grid::{Cell, Grid};
use crate::math::bits::Bits;
use heapless::Vec;

/// A fixed-capacity backtracking list with membership bitsets for maps of
/// up to `NW * 32` cells.
pub struct BacktrackList<const LCAP: usize, const NW: usize> {
    items: Vec<Cell, LCAP>,
    in_list: Bits<NW>,
    abandoned: Bits<NW>,
    inserted: u32,
    overflows: u32,
}

impl<const LCAP: usize, const NW: usize> BacktrackList<LCAP, NW> {
    /// An empty list (usable in a `static`).
    pub const fn new() -> Self {
        Self {
            items: Vec::new(),
            in_list: Bits::new(),
            abandoned: Bits::new(),
            inserted: 0,
            overflows: 0,
        }
    }

    /// Empties the list and forgets given-up goals and counters.
    pub fn reset(&mut self) {
        self.items.clear();
        self.in_list.clear_all();
        self.abandoned.clear_all();
        self.inserted = 0;
        self.overflows = 0;
    }

    /// The points, in insertion order (with removals swapped in).
    pub fn as_slice(&self) -> &[Cell] {
        &self.items
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Points ever inserted since the last reset.
    pub fn inserted(&self) -> u32 {
        self.inserted
    }

    /// Points dropped because the list was full.
    pub fn overflows(&self) -> u32 {
        self.overflows
    }

    /// True when the cell at grid index `i` is listed.
    pub fn contains_index(&self, i: usize) -> bool {
        self.in_list.get(i)
    }

    /// True when the cell at grid index `i` was given up as unreachable.
    pub fn is_abandoned(&self, i: usize) -> bool {
        self.abandoned.get(i)
    }

    /// Inserts a point (no duplicates, never an abandoned one). False when
    /// the list is full: the point is dropped and counted.
    pub fn push<const GW: usize>(&mut self, grid: &Grid<GW>, c: Cell) -> bool {
        let Some(i) = grid.index(c.x as i32, c.y as i32) else {
            return false;
        };
        if self.in_list.get(i) || self.abandoned.get(i) {
            return true;
        }
        if self.items.push(c).is_err() {
            self.overflows += 1;
            return false;
        }
        self.in_list.put(i, true);
        self.inserted += 1;
        true
    }

    /// Takes the point at grid index `i` off the list, if listed.
    pub fn remove_index(&mut self, i: usize, c: Cell) {
        if !self.in_list.get(i) {
            return;
        }
        self.in_list.put(i, false);
        if let Some(k) = self.items.iter().position(|&p| p == c) {
            // The guard proves swap_remove's assert away (the firmware
            // links no panicking branch).
            if k < self.items.len() {
                self.items.swap_remove(k);
            }
        }
    }

    /// Keeps only the points for which `keep` is true.
    pub fn retain<const GW: usize>(
        &mut self,
        grid: &Grid<GW>,
        mut keep: impl FnMut(&Grid<GW>, Cell) -> bool,
    ) {
        let mut k = 0;
        while let Some(&c) = self.items.get(k) {
            if keep(grid, c) {
                k += 1;
                continue;
            }
            if let Some(i) = grid.index(c.x as i32, c.y as i32) {
                self.in_list.put(i, false);
            }
            // The guard proves swap_remove's assert away (the firmware
            // links no panicking branch).
            if k < self.items.len() {
                self.items.swap_remove(k);
            }
        }
    }

    /// Gives up the goal `c` for good (until [`Self::forget_abandoned`]):
    /// marks it and takes it off the list. True when it was new.
    pub fn abandon<const GW: usize>(&mut self, grid: &Grid<GW>, c: Cell) -> bool {
        let mut new = false;
        if let Some(i) = grid.index(c.x as i32, c.y as i32) {
            new = !self.abandoned.get(i);
            self.abandoned.put(i, true);
        }
        self.retain(grid, |_, p| p != c);
        new
    }

    /// Forgets every given-up goal; returns how many there were.
    pub fn forget_abandoned(&mut self) -> u32 {
        let n = self.abandoned.count_prefix(NW * 32);
        if n > 0 {
            self.abandoned.clear_all();
        }
        n as u32
    }
}

impl<const LCAP: usize, const NW: usize> Default for BacktrackList<LCAP, NW> {
    fn default() -> Self {
        Self::new()
    }
}
