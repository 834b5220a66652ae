//! Lidar mapping: scans are ray-cast into a fine evidence grid, and the
//! planner's coarse grid is derived from it with the robot's footprint
//! inflated.
//!
//! **Evidence.** Each cell holds a signed 4-bit counter (two cells a
//! byte, so a 12 × 12 m home at 5 cm is 28,800 bytes, not 57,600): a beam
//! passing through adds [`MISS`], a beam ending in it adds [`HIT`],
//! clamped to [`FREE_LIMIT`]..=[`LIMIT`]. A cell is occupied at ≥
//! [`OCCUPIED_AT`], free at ≤ [`FREE_AT`], unknown in between. A
//! well-seen free cell sits at −8, so one bad return (+3) leaves it free
//! and four in a row (a person stepping in) make it occupied; a well-seen
//! wall (+6) survives six beams through it and turns free at the seventh
//! (a chair moved away). The counters were bytes clamped to ±20 before
//! issue 11 §3; 4 bits keep the same steps and a shorter memory.
//!
//! **Frames.** World coordinates are millimetres with x east and y north
//! and the origin at the map's bottom-left corner; the robot's pose is in
//! that frame (x forward, θ counter-clockwise). Cells are addressed like
//! [`Grid`]: column from the left, row from the top.
//!
//! **Beams** are traced with an exact integer walk over the cells the
//! segment from the lidar to half a cell past the return passes through
//! ([`crate::robot::beam::walk`]); the cell there gets the hit. Returns of 0 (no echo) are skipped;
//! returns beyond the maximum range clear the beam up to that range and
//! mark nothing.

use crate::grid::{Grid, GridError, Zone, ZoneError, Zones};
pub use crate::robot::beam::LidarMount;
use crate::robot::beam::{beams, walk, Beam};
use crate::robot::lidar::scan::Scan;

mod scroll;

/// Evidence added by a beam ending in a cell.
pub const HIT: i8 = 3;
/// Evidence added by a beam passing through a cell.
pub const MISS: i8 = -1;
/// Upper counter limit (a well-seen wall).
pub const LIMIT: i8 = 6;
/// Lower counter limit (a well-seen free cell): the nibble's least value.
pub const FREE_LIMIT: i8 = -8;
/// Occupied at or above.
pub const OCCUPIED_AT: i8 = 2;
/// Free at or below.
pub const FREE_AT: i8 = -1;
/// A wall of the prior map (known mode, after [`EvidenceMap::freeze_prior`]),
/// or a contact the bumper felt ([`EvidenceMap::mark_contact`]):
/// occupied, and never changed by what the lidar sees, so drift cannot
/// write itself into the map the robot localises against. What the lidar
/// adds (people, a moved chair) lives in the other cells' counters, apart
/// from it.
pub const PRIOR_WALL: i8 = 7;

/// Bytes of an evidence map of `cells` cells (two cells a byte): the
/// const parameter of [`EvidenceMap`].
pub const fn evidence_bytes(cells: usize) -> usize {
    cells.div_ceil(2)
}

/// What the map says about a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CellState {
    /// Not seen (or conflicting evidence).
    Unknown,
    /// Seen free.
    Free,
    /// Seen occupied.
    Occupied,
}

/// The state an evidence counter stands for.
fn state_of(e: i8) -> CellState {
    if e >= OCCUPIED_AT {
        CellState::Occupied
    } else if e <= FREE_AT {
        CellState::Free
    } else {
        CellState::Unknown
    }
}

/// A box of cells, corners inclusive: (x0, y0, x1, y1).
pub type CellBox = (i32, i32, i32, i32);

/// The empty box (its corners crossed): [`union_box`]'s identity.
pub const NO_CELLS: CellBox = (i32::MAX, i32::MAX, i32::MIN, i32::MIN);

/// The smallest box holding `a` and `b` (either may be [`NO_CELLS`]).
#[inline]
pub fn union_box(a: CellBox, b: CellBox) -> CellBox {
    (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3))
}

/// Takes the box out of `b`, leaving [`NO_CELLS`]; None when it was empty.
pub fn take_box(b: &mut CellBox) -> Option<CellBox> {
    let t = core::mem::replace(b, NO_CELLS);
    (t.0 <= t.2).then_some(t)
}

/// A fine evidence grid of `B` bytes: up to `2 × B` cells of 4 bits (size
/// it with [`evidence_bytes`]).
#[derive(Clone)]
pub struct EvidenceMap<const B: usize> {
    width: u32,
    height: u32,
    res_mm: u32,
    /// The cells whose state changed since [`Self::take_changed`]: what
    /// the grids derived from the map must look at again.
    /// [`NO_CELLS`] when none did (a plain box: a cell's note is four
    /// comparisons, in the ray-cast's inner loop).
    changed: CellBox,
    /// The owner's no-go zones and virtual walls: a planning rule beside
    /// the evidence, never in it ([`crate::grid::zones`]).
    zones: Zones,
    /// Cell `i` is the low nibble of byte `i / 2` when `i` is even, the
    /// high one when odd; two's complement.
    nibbles: [u8; B],
}

impl<const B: usize> Default for EvidenceMap<B> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const B: usize> EvidenceMap<B> {
    /// An empty 0×0 map.
    pub const fn new() -> Self {
        Self {
            width: 0,
            height: 0,
            res_mm: 1,
            changed: NO_CELLS,
            zones: Zones::new(),
            nibbles: [0; B],
        }
    }

    /// The box of the cells whose state ([`CellState`]) changed since the
    /// last call (None: none did), and forgets it. A grid derived from
    /// the states alone (a configuration space) need only be derived
    /// again around it.
    pub fn take_changed(&mut self) -> Option<CellBox> {
        take_box(&mut self.changed)
    }

    /// Sizes the map to `width × height` cells of `res_mm`, all unknown.
    pub fn reset(&mut self, width: u32, height: u32, res_mm: u32) -> Result<(), GridError> {
        if width == 0 || height == 0 || res_mm == 0 {
            return Err(GridError::Empty);
        }
        let cells = (B as u64).saturating_mul(2);
        if width as u64 * height as u64 > cells {
            return Err(GridError::TooLarge {
                width,
                height,
                capacity: cells.min(u32::MAX as u64) as u32,
            });
        }
        self.width = width;
        self.height = height;
        self.changed = NO_CELLS;
        self.zones = Zones::new();
        self.res_mm = res_mm;
        self.nibbles.iter_mut().for_each(|c| *c = 0);
        Ok(())
    }

    /// Sets the owner's no-go zones and virtual walls (world mm), each
    /// grown by `margin_mm`, after [`Self::reset`] (which clears them) and
    /// before the mission begins. All or nothing.
    pub fn set_zones(&mut self, zones: &[Zone], margin_mm: u32) -> Result<(), ZoneError> {
        self.zones.set(zones, self.height, self.res_mm, margin_mm)
    }

    /// True when the body must not overlap cell (cx, cy): it lies in a
    /// no-go zone or on a virtual wall. Not a wall for the scan matcher.
    #[inline]
    pub fn in_zone(&self, cx: i32, cy: i32) -> bool {
        self.zones.blocks(cx, cy, self.res_mm)
    }

    /// How many zones are set.
    pub fn zone_count(&self) -> usize {
        self.zones.len()
    }

    /// The map's cells as stored, two a byte (see [`Self::reset`]'s size):
    /// what a saved map keeps ([`crate::robot::map_image`]).
    pub fn cell_bytes(&self) -> &[u8] {
        let n = (self.width as usize * self.height as usize).div_ceil(2);
        self.nibbles.get(..n).unwrap_or(&[])
    }

    /// [`Self::cell_bytes`] to be filled, after [`Self::reset`] sized the
    /// map: loading a saved map.
    pub fn cell_bytes_mut(&mut self) -> &mut [u8] {
        let n = (self.width as usize * self.height as usize).div_ceil(2);
        self.nibbles.get_mut(..n).unwrap_or(&mut [])
    }

    /// Empties the map (0 × 0 cells, no zones) in place: no 29 KB value
    /// built on the stack.
    pub fn clear(&mut self) {
        self.width = 0;
        self.height = 0;
        self.changed = NO_CELLS;
        self.zones = Zones::new();
    }

    /// Width in cells.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in cells.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Cell side, mm.
    pub fn res_mm(&self) -> u32 {
        self.res_mm
    }

    fn index(&self, cx: i32, cy: i32) -> Option<usize> {
        (cx >= 0 && cy >= 0 && (cx as u32) < self.width && (cy as u32) < self.height)
            .then(|| cy as usize * self.width as usize + cx as usize)
    }

    /// The cell (column, row from the top) holding world point (x, y) mm.
    pub fn cell_of(&self, x_mm: i32, y_mm: i32) -> (i32, i32) {
        // In i64 and clamped to ±2^30: no overflow for any pose, and the
        // differences `trace` takes stay in range.
        let r = self.res_mm.max(1) as i64;
        let cx = (x_mm as i64).div_euclid(r);
        let cy = self.height as i64 - 1 - (y_mm as i64).div_euclid(r);
        let clamp = |v: i64| v.clamp(-(1 << 30), 1 << 30) as i32;
        (clamp(cx), clamp(cy))
    }

    /// The evidence counter of a cell (0 off the map).
    pub fn evidence(&self, cx: i32, cy: i32) -> i8 {
        self.index(cx, cy).map_or(0, |i| self.get(i))
    }

    /// Counter `i` (0 beyond the buffer).
    fn get(&self, i: usize) -> i8 {
        let byte = self.nibbles.get(i / 2).copied().unwrap_or(0);
        let nib = if i.is_multiple_of(2) {
            byte << 4
        } else {
            byte & 0xF0
        };
        // Sign-extend the nibble from the byte's top half.
        (nib as i8) >> 4
    }

    /// Sets counter `i` to `v` (in −8..=7; beyond the buffer: ignored).
    fn put(&mut self, i: usize, v: i8) {
        if let Some(byte) = self.nibbles.get_mut(i / 2) {
            let nib = (v as u8) & 0x0F;
            *byte = if i.is_multiple_of(2) {
                (*byte & 0xF0) | nib
            } else {
                (*byte & 0x0F) | (nib << 4)
            };
        }
    }

    /// Sets a cell to a definite state (a prior map): [`LIMIT`] or
    /// [`FREE_LIMIT`] evidence, or 0 for unknown. Off the map: ignored.
    /// Not recorded for [`Self::take_changed`]: a prior map is loaded
    /// before a mission begins, and the mission derives its grids whole
    /// then.
    pub fn set_state(&mut self, cx: i32, cy: i32, st: CellState) {
        if let Some(i) = self.index(cx, cy) {
            let v = match st {
                CellState::Occupied => LIMIT,
                CellState::Free => FREE_LIMIT,
                CellState::Unknown => 0,
            };
            self.put(i, v);
        }
    }

    /// What the map says about a cell (off the map: unknown).
    pub fn state(&self, cx: i32, cy: i32) -> CellState {
        state_of(self.evidence(cx, cy))
    }

    /// Adds `d` to a cell's evidence; true when its state changed.
    fn add(&mut self, cx: i32, cy: i32, d: i8) -> bool {
        let Some(i) = self.index(cx, cy) else {
            return false;
        };
        let c = self.get(i);
        if c == PRIOR_WALL {
            return false;
        }
        let n = c.saturating_add(d).clamp(FREE_LIMIT, LIMIT);
        // Most updates leave a settled cell as it was (a free cell at the
        // floor, a wall at the top): nothing to write.
        if n == c {
            return false;
        }
        self.put(i, n);
        (n >= OCCUPIED_AT) != (c >= OCCUPIED_AT) || (n <= FREE_AT) != (c <= FREE_AT)
    }

    /// The bumper felt something at world point (x_mm, y_mm) that the lidar
    /// does not see: its cell becomes a fixed wall ([`PRIOR_WALL`]), noted
    /// for [`Self::take_changed`], so the configuration space and the plan
    /// keep the body off it for the rest of the mission. Fixed, because
    /// what the bumper finds the lidar cannot confirm or clear: beams pass
    /// through a glass pane and would wipe an ordinary wall's evidence
    /// within a few revolutions, and the robot would bump it again. True
    /// when the cell's state changed (it was not a wall already).
    pub fn mark_contact(&mut self, x_mm: i32, y_mm: i32) -> bool {
        let (cx, cy) = self.cell_of(x_mm, y_mm);
        let Some(i) = self.index(cx, cy) else {
            return false;
        };
        let before = self.get(i);
        if before == PRIOR_WALL {
            return false;
        }
        self.put(i, PRIOR_WALL);
        self.changed = union_box(self.changed, (cx, cy, cx, cy));
        before < OCCUPIED_AT
    }

    /// Known mode: turns every occupied cell into a [`PRIOR_WALL`], fixed
    /// from now on. Returns the number of walls frozen.
    pub fn freeze_prior(&mut self) -> u32 {
        self.recode(|e| e >= OCCUPIED_AT, PRIOR_WALL)
    }

    /// Sets every cell whose evidence passes `which` to `to`; returns how
    /// many did. No change is noted ([`Self::take_changed`]).
    fn recode(&mut self, which: impl Fn(i8) -> bool, to: i8) -> u32 {
        let mut n = 0;
        let cells = self.width as usize * self.height as usize;
        for i in 0..cells {
            if which(self.get(i)) {
                self.put(i, to);
                n += 1;
            }
        }
        n
    }

    /// A saved map loaded for an unknown-mode run
    /// ([`crate::mission::MissionConfig::prior_saved`]): turns every
    /// [`PRIOR_WALL`] into a well-seen wall ([`LIMIT`]) that the lidar
    /// keeps up to date, as it does the rest of the map. A map saved by a
    /// known-mode run holds all its walls as `PRIOR_WALL`, the value of a
    /// bumper's mark; left so, [`Self::forget_contacts`] would free every
    /// wall of the home (the studio's power-loss rerun lost itself with
    /// its pose 7 mm right: no wall was left to match), and walls frozen
    /// where the first run drifted could never be corrected. The earlier
    /// run's bumper marks become ordinary walls too: what the lidar cannot
    /// see there, it clears, and the bumper marks it again. Returns the
    /// cells thawed.
    pub fn thaw_prior(&mut self) -> u32 {
        self.recode(|e| e == PRIOR_WALL, LIMIT)
    }

    /// Unknown mode: turns every contact the bumper marked
    /// ([`Self::mark_contact`]) back into a free cell that the lidar judges
    /// again (one hit makes it occupied). For a robot boxed in by its own
    /// marks: a person who walked into it is marked like a table's
    /// crossbar, and a mark in a narrow passage can cut the way home. What
    /// the lidar cannot see is bumped, and marked, again. Not for known
    /// mode, where the prior's walls are the same value. Returns the cells
    /// freed.
    pub fn forget_contacts(&mut self) -> u32 {
        let n = self.recode(|e| e == PRIOR_WALL, FREE_AT);
        if n > 0 {
            self.changed = (0, 0, self.width as i32 - 1, self.height as i32 - 1);
        }
        n
    }

    /// [`Self::forget_contacts`] within `reach` cells (a square) of cell
    /// (cx, cy) only: the marks that shut a robot in, not those that keep
    /// it off a glass pane across the home. Returns the cells freed.
    pub fn forget_contacts_near(&mut self, cx: i32, cy: i32, reach: i32) -> u32 {
        let mut n = 0;
        for y in cy - reach..=cy + reach {
            for x in cx - reach..=cx + reach {
                let Some(i) = self.index(x, y) else {
                    continue;
                };
                if self.get(i) == PRIOR_WALL {
                    self.put(i, FREE_AT);
                    self.changed = union_box(self.changed, (x, y, x, y));
                    n += 1;
                }
            }
        }
        n
    }

    /// A hit within one cell of a prior wall is that wall seen with range
    /// noise (known mode): it adds nothing, so noisy returns do not thicken
    /// the prior's walls into the free cells before them.
    fn near_prior_wall(&self, cx: i32, cy: i32) -> bool {
        (-1..=1).any(|dy| (-1..=1).any(|dx| self.evidence(cx + dx, cy + dy) == PRIOR_WALL))
    }

    /// True for a wall the scan matcher aligns to: a prior wall when
    /// `prior_only` (known mode), any occupied cell otherwise.
    pub fn is_wall(&self, cx: i32, cy: i32, prior_only: bool) -> bool {
        let e = self.evidence(cx, cy);
        if prior_only {
            e == PRIOR_WALL
        } else {
            e >= OCCUPIED_AT
        }
    }

    /// True for a wall cell ([`Self::is_wall`]) with a cell beside it
    /// (4-neighbour) that is not one: the face a lidar can see. The
    /// inside of a thick wall, and the solid never-seen space round a
    /// home a prior map may hold, are walls with no face.
    pub fn is_wall_face(&self, cx: i32, cy: i32, prior_only: bool) -> bool {
        let wall = |x, y| self.is_wall(x, y, prior_only);
        wall(cx, cy)
            && !(wall(cx - 1, cy) && wall(cx + 1, cy) && wall(cx, cy - 1) && wall(cx, cy + 1))
    }

    /// Ray-casts every point of a scan; returns the number of cells
    /// updated.
    pub fn integrate_scan<const F: usize>(&mut self, scan: &Scan<F>, mount: &LidarMount) -> u32 {
        let mut updated = 0u32;
        // A return lies on the obstacle's face; half a cell further along
        // the beam is inside it, so the hit lands in the obstacle's cell
        // rather than the free one before it.
        let past_hit = self.res_mm as i64 / 2;
        for (pose, frame) in scan.frames() {
            beams(pose, mount, frame, past_hit, |b| {
                updated += self.trace_beam(b);
            });
        }
        updated
    }

    /// Marks the cells from (x0, y0) to (x1, y1) (world mm): free along the
    /// way, occupied at the end when `hit`.
    pub fn trace(&mut self, x0: i32, y0: i32, x1: i32, y1: i32, hit: bool) -> u32 {
        self.trace_beam(&Beam {
            origin: (x0, y0),
            end: (x1, y1),
            past: (x1, y1),
            hit,
        })
    }

    /// Marks one beam: every cell the segment from the origin to `past`
    /// truly passes through ([`walk`]) is free, except `past`'s own cell,
    /// which a hit marks (half a cell beyond the return, inside the
    /// obstacle) and a beam with no return clears. Walking to `past`
    /// rather than to the return keeps the Bresenham line's reach (only
    /// the cells between changed): stopping at the return's cell was
    /// tried and thickened walls, losing coverage along them.
    pub fn trace_beam(&mut self, b: &Beam) -> u32 {
        let (mut n, mut ch) = self.walk_free(b.origin, b.past);
        let (ex, ey) = self.cell_of(b.past.0, b.past.1);
        let end = if b.hit {
            !self.near_prior_wall(ex, ey) && self.add(ex, ey, HIT)
        } else {
            self.add(ex, ey, MISS)
        };
        if end {
            ch = union_box(ch, (ex, ey, ex, ey));
        }
        self.changed = union_box(self.changed, ch);
        n += 1;
        n
    }

    /// Adds [`MISS`] to every cell the segment a → b passes through before
    /// b's cell ([`walk`]); the cells visited and the box of those whose
    /// state changed.
    fn walk_free(&mut self, a: (i32, i32), b: (i32, i32)) -> (u32, CellBox) {
        let (mut n, mut ch) = (0u32, NO_CELLS);
        let top = self.height as i64 - 1;
        walk(a, b, self.res_mm, |ix, iy| {
            let (cx, cy) = (ix as i32, (top - iy) as i32);
            if self.add(cx, cy, MISS) {
                ch = union_box(ch, (cx, cy, cx, cy));
            }
            n += 1;
        });
        (n, ch)
    }

    /// Derives the planner's grid (cells of `cell_mm`, the same world
    /// origin): a planner cell is free when a robot of `robot_radius_mm`
    /// centred on it overlaps no occupied evidence cell (and, when
    /// `unknown_blocks`, no unknown one). The grid is resized to cover the
    /// map.
    pub fn derive_grid<const GW: usize>(
        &self,
        grid: &mut Grid<GW>,
        cell_mm: u32,
        robot_radius_mm: u32,
        unknown_blocks: bool,
    ) -> Result<(), GridError> {
        let cell = cell_mm.max(1);
        let (wmm, hmm) = (self.width * self.res_mm, self.height * self.res_mm);
        let (gw, gh) = (wmm / cell, hmm / cell);
        grid.reset(gw, gh)?;
        let res = self.res_mm as i64;
        let reach = robot_radius_mm as i64 + res / 2;
        let r2 = reach * reach;
        for gy in 0..gh as i32 {
            for gx in 0..gw as i32 {
                // Planner cell centre in world mm (row 0 at the top).
                let px = (gx as i64 * cell as i64) + cell as i64 / 2;
                let py = hmm as i64 - (gy as i64 * cell as i64 + cell as i64 / 2);
                let (c0x, c0y) = self.cell_of((px - reach) as i32, (py + reach) as i32);
                let (c1x, c1y) = self.cell_of((px + reach) as i32, (py - reach) as i32);
                let mut blocked = false;
                'scan: for cy in c0y..=c1y {
                    for cx in c0x..=c1x {
                        let ccx = cx as i64 * res + res / 2;
                        let ccy = (self.height as i64 - 1 - cy as i64) * res + res / 2;
                        if (ccx - px).pow(2) + (ccy - py).pow(2) > r2 {
                            continue;
                        }
                        let st = if self.index(cx, cy).is_some() {
                            self.state(cx, cy)
                        } else {
                            CellState::Occupied // the map's edge is a wall
                        };
                        if st == CellState::Occupied || (unknown_blocks && st == CellState::Unknown)
                        {
                            blocked = true;
                            break 'scan;
                        }
                    }
                }
                if blocked {
                    grid.set_obstacle(gx, gy, true)?;
                }
            }
        }
        Ok(())
    }
}
