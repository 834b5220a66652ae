//! Spanning-tree coverage (seed 004, ALGORITHMS.md §5; Gabriely and Rimon
//! 2001).
//!
//! The grid is merged into 2 × 2 **mega-cells** (aligned to even
//! coordinates). A spanning tree joins the mega-cells whose four cells are
//! free, found by depth-first search; the robot then **circumnavigates the
//! tree**, cell by cell, keeping it on one side. A cell lies on one
//! vertical side `vs` (N or S) and one horizontal side `hs` (W or E) of its
//! mega-cell M, and exactly two moves are allowed from it:
//! - toward `vs`: out of M into the next mega-cell when the tree has the
//!   edge from M toward `vs`; else sideways inside M, across the half-axis
//!   where that edge would lie;
//! - toward `hs`: likewise, out of M along the edge toward `hs`, else up or
//!   down inside M.
//!
//! The allowed moves form one cycle through every cell of the tree's
//! mega-cells, each visited once: the robot takes the one not yet covered.
//!
//! **Our decisions.**
//! - **Cells a 2 × 2 block cannot hold** (beside walls, in one-cell
//!   corridors, on an odd map's last row or column) are not in the tree.
//!   No coverage is lost there: when the circuit ends, the shared rescan
//!   lists the uncovered regions' corners and the planner reaches the
//!   nearest with A* octile, where the circuit of any tree it lands on goes
//!   on; cells outside every tree are cleaned by those transits' cover
//!   steps.
//! - **A forest.** Mega-cells that narrow passages split into several
//!   groups get one tree each (a search from every mega-cell not yet in
//!   one, in reading order).
//! - The tree is built at start and at every rescan over the mega-cells
//!   whose cells are free and uncovered (the robot's own cell counts as
//!   uncovered), so a growing map (unknown mode) gets trees for its new
//!   parts. The search walks back through parent links kept in the field:
//!   no stack.
//! - The field holds, at each mega-cell's top-left cell, its tree edges (4
//!   bits), whether it is in a tree, and its parent's direction.

use crate::coverage::cells::{uncovered, E_, N_, S_, W_};
use crate::coverage::rules::{ListRule, LocalMove, Priority, Rules};
use crate::grid::{Cell, Grid};
use crate::search::{Algo, MAX_GOALS};

/// STC's rules.
pub const RULES: Rules = Rules {
    priority: Priority::Fixed([N_, S_, E_, W_]),
    local: LocalMove::SpanningTree,
    list: ListRule::RescanOnly,
    transit_goals: MAX_GOALS,
    transit: Algo::AStarOctile,
    prune_transit: true,
};

/// Directions of the tree's edges, in the order the search tries them.
const DIRS: [(i32, i32); 4] = [N_, W_, S_, E_];
/// The mega-cell is in a tree.
const IN_TREE: u16 = 1 << 4;
/// Bits 5–6: the parent's direction (an index into `DIRS`); bit 7: has one.
const HAS_PARENT: u16 = 1 << 7;

fn edge_bit(d: usize) -> u16 {
    1 << d
}

/// The field index of mega-cell (mx, my)'s top-left cell.
fn slot(w: usize, mx: i32, my: i32) -> usize {
    (2 * my) as usize * w + (2 * mx) as usize
}

/// True when mega-cell (mx, my) joins a tree: its four cells free and
/// uncovered, `cur` counting as uncovered.
fn joins<const GW: usize>(grid: &Grid<GW>, mx: i32, my: i32, cur: Cell) -> bool {
    (0..4).all(|q| {
        let (x, y) = (2 * mx + (q & 1), 2 * my + (q >> 1));
        uncovered(grid, x, y) || (grid.is_free(x, y) && (x, y) == cur.xy())
    })
}

/// Builds the spanning forest into `field` (which holds the grid's cells).
pub fn build<const GW: usize>(grid: &Grid<GW>, field: &mut [u16], cur: Cell) {
    let (w, h) = (grid.width() as usize, grid.height() as usize);
    let Some(f) = field.get_mut(..w * h) else {
        return;
    };
    f.fill(0);
    let (mw, mh) = ((w / 2) as i32, (h / 2) as i32);
    for my in 0..mh {
        for mx in 0..mw {
            let s = slot(w, mx, my);
            if f.get(s).is_some_and(|v| v & IN_TREE == 0) && joins(grid, mx, my, cur) {
                grow(grid, f, (mx, my), (mw, mh), cur);
            }
        }
    }
}

/// Depth-first search from the root mega-cell, backing up through parent
/// links.
fn grow<const GW: usize>(
    grid: &Grid<GW>,
    f: &mut [u16],
    root: (i32, i32),
    (mw, mh): (i32, i32),
    cur: Cell,
) {
    let w = grid.width() as usize;
    let set = |f: &mut [u16], s: usize, bits: u16| {
        if let Some(v) = f.get_mut(s) {
            *v |= bits;
        }
    };
    set(f, slot(w, root.0, root.1), IN_TREE);
    let (mut mx, mut my) = root;
    loop {
        let s = slot(w, mx, my);
        let next = DIRS.iter().enumerate().find(|&(_, &(dx, dy))| {
            let (nx, ny) = (mx + dx, my + dy);
            nx >= 0
                && ny >= 0
                && nx < mw
                && ny < mh
                && f.get(slot(w, nx, ny)).is_some_and(|v| v & IN_TREE == 0)
                && joins(grid, nx, ny, cur)
        });
        if let Some((d, &(dx, dy))) = next {
            let (nx, ny) = (mx + dx, my + dy);
            let back = (d + 2) % 4;
            set(f, s, edge_bit(d));
            let parent = IN_TREE | edge_bit(back) | HAS_PARENT | ((back as u16) << 5);
            set(f, slot(w, nx, ny), parent);
            (mx, my) = (nx, ny);
            continue;
        }
        let v = f.get(s).copied().unwrap_or(0);
        if v & HAS_PARENT == 0 {
            return;
        }
        let Some(&(dx, dy)) = DIRS.get(((v >> 5) & 3) as usize) else {
            return;
        };
        (mx, my) = (mx + dx, my + dy);
    }
}

/// The two moves the circuit allows from cell (x, y), when its mega-cell
/// is in a tree. With `vs` the mega-cell's side the cell is on vertically
/// (N or S) and `hs` horizontally (W or E): the cell leaves the mega-cell
/// toward `vs` when the tree has that edge, else it crosses the half-axis
/// toward `vs` to its horizontal neighbour inside; likewise toward `hs`.
fn circuit_moves<const GW: usize>(
    grid: &Grid<GW>,
    field: &[u16],
    x: i32,
    y: i32,
) -> Option<[(i32, i32); 2]> {
    let w = grid.width() as usize;
    let (mx, my) = (x >> 1, y >> 1);
    let v = *field.get(slot(w, mx, my))?;
    let whole = 2 * mx + 1 < grid.width() as i32 && 2 * my + 1 < grid.height() as i32;
    if v & IN_TREE == 0 || !whole {
        return None;
    }
    let has = |d: (i32, i32)| {
        DIRS.iter()
            .position(|&e| e == d)
            .is_some_and(|k| v & edge_bit(k) != 0)
    };
    let (vs, inside_v) = if y & 1 == 0 { (N_, S_) } else { (S_, N_) };
    let (hs, inside_h) = if x & 1 == 0 { (W_, E_) } else { (E_, W_) };
    let a = if has(vs) { vs } else { inside_h };
    let b = if has(hs) { hs } else { inside_v };
    Some([a, b])
}

/// The next local move: the circuit's uncovered move (the first of the two
/// at the start of a circuit); `None` off the trees or at the circuit's end.
pub fn next_move<const GW: usize>(grid: &Grid<GW>, field: &[u16], cur: Cell) -> Option<Cell> {
    let (x, y) = cur.xy();
    let moves = circuit_moves(grid, field, x, y)?;
    moves.iter().find_map(|&(dx, dy)| {
        if uncovered(grid, x + dx, y + dy) {
            Cell::from_xy(x + dx, y + dy)
        } else {
            None
        }
    })
}
