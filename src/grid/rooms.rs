//! Room segmentation of the planning cells (issue 12, "room by room"): the
//! distance-transform segmentation of ipa_room_segmentation (Bormann,
//! Jordan, Li, Hampp, Hägele, "Room segmentation: survey, implementation,
//! and analysis", ICRA 2016, §III-B "distance transform-based").
//!
//! Why this one: doorways are the narrowest places between rooms, so
//! eroding the free space (thresholding its distance transform) cuts the
//! home at its doors first. The threshold that leaves the most room-sized
//! cores is the one that splits the home into its rooms; the cores then
//! grow back over the free space, each cell joining the core whose
//! wavefront reaches it first. It needs one byte a cell and a queue, runs
//! once when a known-mode mission begins, and is exact on integers.
//! (Seed 003's decomposition cuts at every concave corner, furniture's
//! too: regions for a sweep pattern, not rooms an owner would name.)
//!
//! **Our choices (\[open\] in the survey's parameters).** The distance is
//! the chessboard distance in planning cells to the nearest blocked cell
//! (the planning cells are already the configuration space, so a doorway
//! is one or two cells wide). The survey takes one threshold for the whole
//! map; homes mix narrow halls with wide rooms, so ours is applied per
//! seed: the free space's components of at least `min_core_cells` are the
//! first seeds, and at each threshold `2..=max_depth` a seed whose cores
//! include two or more of that size splits into them (a seed with one
//! core stays whole). Cores below the minimum are dropped and their cells
//! grown over. Free cells no wavefront reaches (a pocket cut off from
//! every core) become rooms of their own. Room ids run `1..=MAX_ROOMS`;
//! past that, seeds no longer split and further pockets share the last
//! id (an overflow policy, tested). Nothing is stored but the labels: the
//! distance is tested on the grid as needed (a square of `(2t - 1)²`
//! cells), and marks live in the labels' high bit.

use super::{Cell, Grid};

/// Label of a blocked cell, or of none yet.
pub const NONE: u8 = 0;
/// Most rooms told apart (ids `1..=MAX_ROOMS`).
pub const MAX_ROOMS: u8 = 126;
/// Marks a cell done in this pass (the labels' high bit).
const SEEN: u8 = 0x80;
/// Marks a core cell before it has its id.
const CORE: u8 = 0x7F;
/// Marks the core being given its id.
const BUSY: u8 = 0xFF;

/// The segmentation's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RoomParams {
    /// Largest threshold tried, cells.
    pub max_depth: u8,
    /// Smallest core that counts as a room, cells.
    pub min_core_cells: u16,
}

impl RoomParams {
    /// For 0.3 m planning cells: thresholds up to 1.5 m from a wall, a
    /// core of at least 0.54 m² (six cells; measured on the six Valetudo
    /// homes against their vendors' segments, `host-sim rooms`).
    pub const DEFAULT: Self = Self {
        max_depth: 5,
        min_core_cells: 6,
    };
}

/// What went wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RoomError {
    /// The labels have fewer bytes than the grid has cells.
    LabelsTooSmall,
    /// A wavefront outgrew the queue (the rooms are not split).
    QueueFull,
}

/// The rooms found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rooms {
    /// Rooms (ids `1..=count`).
    pub count: u8,
    /// The deepest threshold at which a seed split, cells (1: none split
    /// but the free space's own components).
    pub depth: u8,
}

/// The room of cell (x, y) in `labels` (as [`segment`] wrote them),
/// [`NONE`] off the grid or the labels.
pub fn label_at<const NW: usize>(grid: &Grid<NW>, labels: &[u8], x: i32, y: i32) -> u8 {
    grid.index(x, y)
        .and_then(|i| labels.get(i))
        .copied()
        .unwrap_or(NONE)
}

/// How many lanes room `id` takes swept in rows and in columns,
/// `(rows, columns)`: its maximal runs of cells along x and along y. Where
/// `joined(a, b)` says two neighbouring cells of a run are not (a thin
/// wall between them, which the planning cells do not show, so the
/// planner's lane runs into it and needs a detour around), the run counts
/// `wall_lanes` lanes more.
/// The mission sweeps a room the way with fewer lanes, so fewer turns:
/// its long axis, measured on the room's own cells rather than its
/// bounding box, which an L-shaped room or a hall's alcove would mislead.
pub fn lanes<const NW: usize>(
    grid: &Grid<NW>,
    labels: &[u8],
    id: u8,
    wall_lanes: u32,
    mut joined: impl FnMut((i32, i32), (i32, i32)) -> bool,
) -> (u32, u32) {
    let (w, h) = (grid.width() as i32, grid.height() as i32);
    let is = |x: i32, y: i32| id != NONE && label_at(grid, labels, x, y) == id;
    let (mut rows, mut cols) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            if is(x, y) {
                let mut lane = |before: (i32, i32)| match is(before.0, before.1) {
                    false => 1,
                    true if joined(before, (x, y)) => 0,
                    true => wall_lanes,
                };
                rows += lane((x - 1, y));
                cols += lane((x, y - 1));
            }
        }
    }
    (rows, cols)
}

/// Splits the free cells of `grid` into rooms: `labels[i]` becomes the
/// room id of cell `i` ([`NONE`] for blocked cells). `queue` holds a
/// wavefront (a few grid perimeters are plenty).
pub fn segment<const NW: usize>(
    grid: &Grid<NW>,
    labels: &mut [u8],
    queue: &mut [Cell],
    p: RoomParams,
) -> Result<Rooms, RoomError> {
    let cells = grid.cells();
    let labels = labels.get_mut(..cells).ok_or(RoomError::LabelsTooSmall)?;
    for (i, l) in labels.iter_mut().enumerate() {
        let (x, y) = grid.cell_at(i).xy();
        *l = if grid.is_blocked(x, y) { NONE } else { 1 };
    }
    let mut count = 1;
    let mut depth = 1;
    for t in 1..=p.max_depth.max(1) {
        // The seeds of the threshold before; new ones split at the next.
        let seeds = count;
        for seed in 1..=seeds {
            let s = Split {
                seed,
                t,
                min: p.min_core_cells,
                always: t == 1,
            };
            let now = split(grid, labels, queue, s, count)?;
            if now != count && t > 1 {
                depth = t;
            }
            count = now;
        }
    }
    grow(grid, labels);
    count = label_pockets(grid, labels, queue, count)?;
    Ok(Rooms { count, depth })
}

/// Cell `i` is at least `t` cells (chessboard) from a blocked or off-map
/// cell: every cell of the square of radius `t - 1` around it is free.
fn deep<const NW: usize>(grid: &Grid<NW>, i: usize, t: u8) -> bool {
    let (x, y) = grid.cell_at(i).xy();
    let r = t as i32 - 1;
    (-r..=r).all(|dy| (-r..=r).all(|dx| grid.is_free(x + dx, y + dy)))
}

/// The four neighbours of a cell.
const STEPS: [(i32, i32); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];

/// A ring queue over a caller's buffer of cells.
struct Ring<'a> {
    buf: &'a mut [Cell],
    head: usize,
    len: usize,
}

impl<'a> Ring<'a> {
    fn new(buf: &'a mut [Cell]) -> Self {
        Self {
            buf,
            head: 0,
            len: 0,
        }
    }

    fn push(&mut self, c: Cell) -> Result<(), RoomError> {
        let cap = self.buf.len();
        if self.len >= cap {
            return Err(RoomError::QueueFull);
        }
        let slot = self.buf.get_mut((self.head + self.len) % cap);
        *slot.ok_or(RoomError::QueueFull)? = c;
        self.len += 1;
        Ok(())
    }

    fn pop(&mut self) -> Option<Cell> {
        if self.len == 0 {
            return None;
        }
        let c = *self.buf.get(self.head)?;
        self.head = (self.head + 1) % self.buf.len();
        self.len -= 1;
        Some(c)
    }
}

/// Floods the 4-connected cells around `from` for which `inside(index,
/// label)` holds, relabelling each `to(label)`; the cells flooded. A
/// relabelled cell must not be `inside`.
fn flood<const NW: usize>(
    grid: &Grid<NW>,
    labels: &mut [u8],
    queue: &mut [Cell],
    from: Cell,
    inside: impl Fn(usize, u8) -> bool,
    to: impl Fn(u8) -> u8,
) -> Result<u16, RoomError> {
    let mut ring = Ring::new(queue);
    let mut n = 0u16;
    let (fx, fy) = from.xy();
    if let Some(l) = grid.index(fx, fy).and_then(|i| labels.get_mut(i)) {
        *l = to(*l);
    }
    ring.push(from)?;
    while let Some(c) = ring.pop() {
        n = n.saturating_add(1);
        let (x, y) = c.xy();
        for (dx, dy) in STEPS {
            let Some(i) = grid.index(x + dx, y + dy) else {
                continue;
            };
            let Some(l) = labels.get_mut(i) else { continue };
            if inside(i, *l) {
                *l = to(*l);
                ring.push(grid.cell_at(i))?;
            }
        }
    }
    Ok(n)
}

/// One seed's split at one threshold.
#[derive(Clone, Copy)]
struct Split {
    /// The seed (a room id).
    seed: u8,
    /// The threshold, cells.
    t: u8,
    /// Smallest core kept, cells.
    min: u16,
    /// Keep only its big cores even when there is just one (the first
    /// threshold: small pockets of free space are no room's seed).
    always: bool,
}

/// Splits seed `s.seed` into its cores at threshold `s.t` when it has two
/// or more of at least `s.min` cells (the first keeps the seed's id, the
/// others take new ones; the rest of the seed's cells are let go, to be
/// grown over). The rooms now labelled.
fn split<const NW: usize>(
    grid: &Grid<NW>,
    labels: &mut [u8],
    queue: &mut [Cell],
    s: Split,
    mut count: u8,
) -> Result<u8, RoomError> {
    let (seed, t) = (s.seed, s.t);
    let mut big = 0u16;
    for i in 0..labels.len() {
        if labels.get(i) != Some(&seed) || !deep(grid, i, t) {
            continue;
        }
        let inside = |j: usize, l: u8| l == seed && deep(grid, j, t);
        let size = flood(grid, labels, queue, grid.cell_at(i), inside, |_| CORE)?;
        big += (size >= s.min) as u16;
    }
    if big < 2 && !s.always || big >= 2 && count >= MAX_ROOMS {
        for l in labels.iter_mut().filter(|l| **l == CORE) {
            *l = seed;
        }
        return Ok(count);
    }
    let mut first = true;
    for i in 0..labels.len() {
        if labels.get(i) != Some(&CORE) {
            continue;
        }
        let c = grid.cell_at(i);
        let size = flood(grid, labels, queue, c, |_, l| l == CORE, |_| BUSY)?;
        let id = match (size >= s.min, first) {
            (false, _) => NONE,
            (true, true) => seed,
            (true, false) => {
                count = (count + 1).min(MAX_ROOMS);
                count
            }
        };
        first &= size < s.min;
        flood(grid, labels, queue, c, |_, l| l == BUSY, |_| id | SEEN)?;
    }
    if first {
        count -= 1; // no core at all: the seed is gone (only at t = 1)
    }
    for l in labels.iter_mut() {
        if *l == seed {
            *l = NONE; // the seed's shallow cells: grown over later
        } else if *l & SEEN != 0 {
            *l &= !SEEN;
        }
    }
    Ok(count)
}

/// Grows the rooms over the free cells, one ring of cells a round, each
/// cell joining the first room whose wavefront reaches it (ties to the
/// neighbour found first: east, west, north, south).
fn grow<const NW: usize>(grid: &Grid<NW>, labels: &mut [u8]) {
    let (w, h) = (grid.width() as i32, grid.height() as i32);
    loop {
        let mut changed = false;
        for y in 0..h {
            for x in 0..w {
                let Some(i) = grid.index(x, y) else { continue };
                if labels.get(i) != Some(&NONE) || grid.is_blocked(x, y) {
                    continue;
                }
                let from = STEPS.iter().find_map(|&(dx, dy)| {
                    let l = *labels.get(grid.index(x + dx, y + dy)?)?;
                    (l != NONE && l & SEEN == 0).then_some(l)
                });
                if let (Some(l), Some(c)) = (from, labels.get_mut(i)) {
                    *c = l | SEEN;
                    changed = true;
                }
            }
        }
        for l in labels.iter_mut() {
            *l &= !SEEN;
        }
        if !changed {
            return;
        }
    }
}

/// Free cells no wavefront reached become rooms of their own (the last
/// id shared once ids run out). The rooms now labelled.
fn label_pockets<const NW: usize>(
    grid: &Grid<NW>,
    labels: &mut [u8],
    queue: &mut [Cell],
    mut count: u8,
) -> Result<u8, RoomError> {
    let unlabelled_free = |i: usize, l: u8| {
        let (x, y) = grid.cell_at(i).xy();
        l == NONE && !grid.is_blocked(x, y)
    };
    for i in 0..labels.len() {
        if !labels.get(i).is_some_and(|&l| unlabelled_free(i, l)) {
            continue;
        }
        count = (count + 1).min(MAX_ROOMS);
        flood(
            grid,
            labels,
            queue,
            grid.cell_at(i),
            unlabelled_free,
            |_| count,
        )?;
    }
    Ok(count)
}
