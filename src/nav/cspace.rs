//! Configuration space: which positions the robot's centre may take, on the
//! coarse planning grid and on the fine grid of the evidence map. Shared by
//! the mission executive (planning cells, edge pass, transit home) and
//! written once here.
//!
//! Geometry is exact for square cells: a position is free when the disc of
//! the robot's radius plus margin around it overlaps no occupied evidence
//! cell (as a closed square; the map's edge counts as a wall). For a wall on
//! a cell boundary and a clearance that is an odd multiple of half the cell
//! side (165 mm + 10 mm = 3.5 × 50 mm), the outermost free fine cells lie
//! exactly at that clearance, so an edge pass along them cleans up to
//! `margin` from the wall.
//!
//! Coordinates here are "index space": mm from the map's top-left corner,
//! x right, y down (evidence cell (cx, cy) spans [cx·res, (cx+1)·res] ×
//! [cy·res, (cy+1)·res]). World y is the map's height in mm minus this y.

use crate::grid::{Grid, GridError};
use crate::robot::lidar_map::{CellBox, CellState, EvidenceMap};

/// Squared distance (mm²) from point (px, py) to the closed square of
/// evidence cell (cx, cy), in index space.
#[inline]
pub fn square_dist2(px: i64, py: i64, cx: i64, cy: i64, res: i64) -> i64 {
    let (x0, y0) = (cx * res, cy * res);
    let dx = (x0 - px).max(0).max(px - (x0 + res));
    let dy = (y0 - py).max(0).max(py - (y0 + res));
    dx * dx + dy * dy
}

/// True when an evidence cell stops the robot: occupied, off the map, in
/// a no-go zone or on a virtual wall ([`EvidenceMap::in_zone`]), or
/// unknown when `unknown_blocks`. Every grid, anchor and clearance check
/// below asks this, so a zone keeps the body out everywhere.
#[inline]
pub fn cell_blocks<const EV: usize>(
    map: &EvidenceMap<EV>,
    cx: i32,
    cy: i32,
    unknown_blocks: bool,
) -> bool {
    if off_map(map, cx, cy) || map.in_zone(cx, cy) {
        return true;
    }
    match map.state(cx, cy) {
        CellState::Occupied => true,
        CellState::Unknown => unknown_blocks,
        CellState::Free => false,
    }
}

/// True for a cell on the rim of a zone (in it, with a 4-neighbour out of
/// it): what the local planner treats as an obstacle point, so a swerve
/// around a person does not cut into a no-go zone.
pub fn zone_rim<const EV: usize>(map: &EvidenceMap<EV>, cx: i32, cy: i32) -> bool {
    map.in_zone(cx, cy)
        && [(1, 0), (-1, 0), (0, 1), (0, -1)]
            .iter()
            .any(|&(dx, dy)| !map.in_zone(cx + dx, cy + dy))
}

/// True when a disc of `radius_mm` at index-space point (px, py) overlaps a
/// blocking evidence cell. Work: (2·radius/res + 3)² cells.
pub fn disc_blocked<const EV: usize>(
    map: &EvidenceMap<EV>,
    px: i64,
    py: i64,
    radius_mm: i64,
    unknown_blocks: bool,
) -> bool {
    disc_any(map, px, py, radius_mm, |cx, cy| {
        cell_blocks(map, cx, cy, unknown_blocks)
    })
}

/// True when (cx, cy) lies outside the map: it blocks, whatever a
/// caller's rule for the cells on it.
fn off_map<const EV: usize>(map: &EvidenceMap<EV>, cx: i32, cy: i32) -> bool {
    cx < 0 || cy < 0 || cx as u32 >= map.width() || cy as u32 >= map.height()
}

/// [`disc_blocked`], counting only cells sure to block: the map's outside,
/// no-go zones and evidence of at least `at_least` (a wall seen again and
/// again, not a cell that flickers at the occupied threshold).
pub fn disc_surely_blocked<const EV: usize>(
    map: &EvidenceMap<EV>,
    px: i64,
    py: i64,
    radius_mm: i64,
    at_least: i8,
) -> bool {
    disc_any(map, px, py, radius_mm, |cx, cy| {
        off_map(map, cx, cy) || map.in_zone(cx, cy) || map.evidence(cx, cy) >= at_least
    })
}

/// True when `blocks` holds for a cell a disc of `radius_mm` at
/// index-space point (px, py) overlaps.
fn disc_any<const EV: usize>(
    map: &EvidenceMap<EV>,
    px: i64,
    py: i64,
    radius_mm: i64,
    blocks: impl Fn(i32, i32) -> bool,
) -> bool {
    let res = map.res_mm().max(1) as i64;
    let r2 = radius_mm * radius_mm;
    let (c0x, c1x) = (
        (px - radius_mm).div_euclid(res),
        (px + radius_mm).div_euclid(res),
    );
    let (c0y, c1y) = (
        (py - radius_mm).div_euclid(res),
        (py + radius_mm).div_euclid(res),
    );
    for cy in c0y..=c1y {
        for cx in c0x..=c1x {
            if square_dist2(px, py, cx, cy, res) < r2 && blocks(cx as i32, cy as i32) {
                return true;
            }
        }
    }
    false
}

/// Sizes `coarse` to planning cells of `cell_mm` over the evidence map
/// (keeping nothing), all free.
pub fn size_coarse<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    coarse: &mut Grid<GW>,
    cell_mm: u32,
) -> Result<(), GridError> {
    let cell = cell_mm.max(1);
    coarse.reset(
        map.width() * map.res_mm() / cell,
        map.height() * map.res_mm() / cell,
    )
}

/// Where the robot stands for planning cell (gx, gy) of `cell_mm`, in
/// index space (always on floor the map has seen free): the cell's centre
/// when the robot fits there, else the
/// fine-cell centre inside the planning cell nearest to it where the robot
/// fits; None when it fits nowhere in the cell. This keeps narrow passages
/// that do not line up with the planning grid (a 0.4 m gap between a
/// counter and a wall) in the plan. Work: up to (cell/res)² + 1 disc
/// checks.
pub fn coarse_anchor<const EV: usize>(
    map: &EvidenceMap<EV>,
    cell_mm: u32,
    radius_mm: u32,
    unknown_blocks: bool,
    gx: i32,
    gy: i32,
) -> Option<(i64, i64)> {
    let cell = cell_mm.max(1) as i64;
    let (x0, y0) = (gx as i64 * cell, gy as i64 * cell);
    let (cx, cy) = (x0 + cell / 2, y0 + cell / 2);
    let r = radius_mm as i64;
    // The robot stands only on floor the map has seen: with unknown space
    // counted as free, a cell beside a sofa whose inside was never seen
    // would otherwise get an anchor inside the sofa.
    let seen = |px: i64, py: i64| {
        let res = map.res_mm().max(1) as i64;
        map.state(px.div_euclid(res) as i32, py.div_euclid(res) as i32) == CellState::Free
    };
    if seen(cx, cy) && !disc_blocked(map, cx, cy, r, unknown_blocks) {
        return Some((cx, cy));
    }
    let res = map.res_mm().max(1) as i64;
    let mut best: Option<(i64, (i64, i64))> = None;
    let mut fy = y0.div_euclid(res);
    while fy * res < y0 + cell {
        let mut fx = x0.div_euclid(res);
        while fx * res < x0 + cell {
            let (px, py) = (fx * res + res / 2, fy * res + res / 2);
            let inside = px >= x0 && px < x0 + cell && py >= y0 && py < y0 + cell;
            let d = (px - cx).pow(2) + (py - cy).pow(2);
            if inside
                && best.is_none_or(|(b, _)| d < b)
                && seen(px, py)
                && !disc_blocked(map, px, py, r, unknown_blocks)
            {
                best = Some((d, (px, py)));
            }
            fx += 1;
        }
        fy += 1;
    }
    best.map(|(_, p)| p)
}

/// World mm of a planning cell's anchor ([`coarse_anchor`]), or its centre
/// when the robot fits nowhere in it.
pub fn anchor_mm<const EV: usize>(
    map: &EvidenceMap<EV>,
    cell_mm: u32,
    radius_mm: u32,
    gx: i32,
    gy: i32,
) -> (i32, i32) {
    let hmm = map.height() as i64 * map.res_mm() as i64;
    match coarse_anchor(map, cell_mm, radius_mm, false, gx, gy) {
        Some((x, y)) => (x as i32, (hmm - y) as i32),
        None => coarse_centre_mm(map, cell_mm, gx, gy),
    }
}

/// Sets every coarse cell's obstacle bit from the evidence map (free when
/// the robot fits somewhere in the cell, see [`coarse_anchor`]), keeping
/// the other layers (the planner's covered cells). Work: cells × up to
/// ((cell/res)² + 1) × (2·radius/res + 3)².
pub fn update_coarse<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    coarse: &mut Grid<GW>,
    cell_mm: u32,
    radius_mm: u32,
    unknown_blocks: bool,
) -> Result<(), GridError> {
    let all = (0, 0, coarse.width() as i32 - 1, coarse.height() as i32 - 1);
    update_coarse_in(map, coarse, cell_mm, radius_mm, unknown_blocks, all)
}

/// [`update_coarse`] on the planning cells of `boxed` (corners inclusive,
/// clipped to the grid) only: the same result when the map's states
/// changed only where [`coarse_box_of`] says.
pub fn update_coarse_in<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    coarse: &mut Grid<GW>,
    cell_mm: u32,
    radius_mm: u32,
    unknown_blocks: bool,
    boxed: CellBox,
) -> Result<(), GridError> {
    let (w, h) = (coarse.width() as i32, coarse.height() as i32);
    for gy in boxed.1.max(0)..=boxed.3.min(h - 1) {
        for gx in boxed.0.max(0)..=boxed.2.min(w - 1) {
            let b = coarse_anchor(map, cell_mm, radius_mm, unknown_blocks, gx, gy).is_none();
            coarse.set_obstacle(gx, gy, b)?;
        }
    }
    Ok(())
}

/// The planning cells (of `cell_mm`) whose anchor may depend on the
/// evidence cells of `fine` (a box of changed cells): [`coarse_anchor`]
/// looks at the cells within `radius_mm` of points inside its planning
/// cell, so the box grows by the radius and one cell each way.
pub fn coarse_box_of(res_mm: u32, cell_mm: u32, radius_mm: u32, fine: CellBox) -> CellBox {
    let (res, cell, r) = (
        res_mm.max(1) as i64,
        cell_mm.max(1) as i64,
        radius_mm as i64,
    );
    let lo = |c: i32| ((c as i64 * res - r).div_euclid(cell) - 1) as i32;
    let hi = |c: i32| (((c as i64 + 1) * res + r).div_euclid(cell) + 1) as i32;
    (lo(fine.0), lo(fine.1), hi(fine.2), hi(fine.3))
}

/// Largest stamp reach, in cells, of [`build_fine`] (3.1 m at 5 cm).
pub const MAX_STAMP_REACH: usize = 63;

/// Builds the fine configuration space on the evidence map's own cells:
/// `fine` gets the map's size, and a cell is blocked when the robot
/// (`radius_mm`, margin included) centred on it overlaps a blocking
/// evidence cell.
///
/// Each blocking cell stamps its neighbourhood, one run of bits a row: the
/// stamp (the cell's square grown by the radius, sampled at cell centres)
/// is the same for every cell, so its half-widths are worked out once.
///
/// A cell inside the map whose four neighbours all block (inside a thick
/// wall) blocks only itself: a free point within the radius of its square
/// is within the radius of a blocking cell with a free neighbour. (Walk
/// from the nearest point of the square to the free point: the last
/// blocking cell passed is left through an edge, to a free neighbour, or
/// through a corner, whose two other cells then border the free diagonal
/// cell; either way a stamping cell's square is no farther.) Work:
/// blocking cells with a free neighbour × (2·reach + 1) row runs, where
/// reach = radius/res + 2. A reach beyond [`MAX_STAMP_REACH`] is refused
/// as [`GridError::TooLarge`].
pub fn build_fine<const EV: usize, const GW: usize>(
    map: &EvidenceMap<EV>,
    fine: &mut Grid<GW>,
    radius_mm: u32,
    unknown_blocks: bool,
) -> Result<(), GridError> {
    let (w, h) = (map.width() as i32, map.height() as i32);
    fine.reset_keeping_covered(w as u32, h as u32)?;
    let res = map.res_mm().max(1) as i64;
    let Some(half) = stamp_half_widths(res, radius_mm as i64) else {
        return Err(GridError::TooLarge {
            width: w as u32,
            height: h as u32,
            capacity: 0,
        });
    };
    let reach = (radius_mm as i64 / res + 2) as i32;
    let inner_skip = radius_mm > 0;
    let blocks = |x: i32, y: i32| cell_blocks(map, x, y, unknown_blocks);
    // The map's edge is a wall: stamp a ring of virtual cells around it.
    for cy in -1..=h {
        for cx in -1..=w {
            let inside = cx >= 0 && cy >= 0 && cx < w && cy < h;
            if inside && !blocks(cx, cy) {
                continue;
            }
            let buried = blocks(cx - 1, cy) && blocks(cx + 1, cy);
            if inside && inner_skip && buried && blocks(cx, cy - 1) && blocks(cx, cy + 1) {
                fine.block_run(cy, cx, cx);
                continue;
            }
            for dy in -reach..=reach {
                let hw = half.get(dy.unsigned_abs() as usize).copied().unwrap_or(-1);
                if hw >= 0 {
                    fine.block_run(cy + dy, cx - hw, cx + hw);
                }
            }
        }
    }
    Ok(())
}

/// Blocks in `fine` what [`build_fine`] blocks for one more blocking
/// evidence cell (cx, cy) of `res_mm` cells, `radius_mm` as there: a grid
/// built before the cell turned to wall and stamped then equals one built
/// after. False (nothing changed) when the reach exceeds
/// [`MAX_STAMP_REACH`].
pub fn stamp_cell<const GW: usize>(
    fine: &mut Grid<GW>,
    res_mm: u32,
    radius_mm: u32,
    (cx, cy): (i32, i32),
) -> bool {
    let res = res_mm.max(1) as i64;
    let Some(half) = stamp_half_widths(res, radius_mm as i64) else {
        return false;
    };
    let reach = (radius_mm as i64 / res + 2) as i32;
    for dy in -reach..=reach {
        let hw = half.get(dy.unsigned_abs() as usize).copied().unwrap_or(-1);
        if hw >= 0 {
            fine.block_run(cy + dy, cx - hw, cx + hw);
        }
    }
    true
}

/// The stamp's half-width in cells for each row offset 0..=reach (−1: the
/// row is not reached): the largest k with the centre of cell (k, dy)
/// nearer than `r` to the closed square of cell (0, 0). `None` when the
/// reach exceeds [`MAX_STAMP_REACH`].
fn stamp_half_widths(res: i64, r: i64) -> Option<[i32; MAX_STAMP_REACH + 1]> {
    let reach = r / res + 2;
    if reach < 0 || reach > MAX_STAMP_REACH as i64 {
        return None;
    }
    let mut half = [-1i32; MAX_STAMP_REACH + 1];
    for (dy, slot) in half.iter_mut().enumerate().take(reach as usize + 1) {
        let py = dy as i64 * res + res / 2;
        for k in 0..=reach {
            if square_dist2(k * res + res / 2, py, 0, 0, res) < r * r {
                *slot = k as i32;
            }
        }
    }
    Some(half)
}

/// World mm of the centre of fine cell (cx, cy).
pub fn fine_centre_mm<const EV: usize>(map: &EvidenceMap<EV>, cx: i32, cy: i32) -> (i32, i32) {
    coarse_centre_mm(map, map.res_mm(), cx, cy)
}

/// World mm of the centre of cell (gx, gy) of a grid of `cell_mm` cells
/// over the evidence map (row 0 at the top).
pub fn coarse_centre_mm<const EV: usize>(
    map: &EvidenceMap<EV>,
    cell_mm: u32,
    gx: i32,
    gy: i32,
) -> (i32, i32) {
    let c = cell_mm as i64;
    let hmm = map.height() as i64 * map.res_mm() as i64;
    (
        (gx as i64 * c + c / 2) as i32,
        (hmm - (gy as i64 * c + c / 2)) as i32,
    )
}

/// The coarse cell of world point (x, y) mm (may be off the grid).
pub fn coarse_of<const EV: usize>(
    map: &EvidenceMap<EV>,
    cell_mm: u32,
    x_mm: i32,
    y_mm: i32,
) -> (i32, i32) {
    let hmm = map.height() as i64 * map.res_mm() as i64;
    coarse_of_mm(hmm, cell_mm, x_mm, y_mm)
}

/// [`coarse_of`] for a map `height_mm` tall: what the real-time control
/// path uses, without the map.
pub fn coarse_of_mm(height_mm: i64, cell_mm: u32, x_mm: i32, y_mm: i32) -> (i32, i32) {
    let c = cell_mm.max(1) as i64;
    (
        (x_mm as i64).div_euclid(c).clamp(-1, 1 << 20) as i32,
        (height_mm - y_mm as i64).div_euclid(c).clamp(-1, 1 << 20) as i32,
    )
}
