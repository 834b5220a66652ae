//! No-go zones and virtual walls: places the owner forbids, kept apart
//! from what the robot sees.
//!
//! A zone is a rule, not an obstacle: the lidar never sees it, so it must
//! not enter the evidence the scan matcher aligns to, and no beam may
//! clear it. It is stored here as a short list (at most [`MAX_ZONES`],
//! a few hundred bytes) and asked per cell by the configuration space
//! ([`crate::nav::cspace::cell_blocks`]): a cell in a zone stops the
//! robot's body like a wall, so every plan, detour and anchor keeps the
//! whole body out of it without a map of its own (a bit a cell would be
//! 7.2 KB for a 12 × 12 m home at 5 cm).
//!
//! Each zone grows by a margin (the pose error the robot allows itself:
//! the body is kept out of the zone by where it *believes* it is).
//!
//! Coordinates are "index space" (mm from the map's top-left corner, x
//! right, y down), cells as in [`crate::grid::Grid`]. Zones reaching past
//! the map are clipped by it (a ValetudoMap no-go area often does).

/// How many zones (no-go areas and virtual walls together) a map holds.
pub const MAX_ZONES: usize = 8;

/// How far the body keeps from a zone beyond touching it, mm: the pose
/// error the robot allows itself. Localisation holds the position within
/// about 60 mm at worst under realistic noise (issue 10's figures), and
/// the cells round a zone outward by up to one more cell, so one cell of
/// margin keeps the true body out in practice. [open] in the digest's
/// terms: the papers have no zones; this is our choice.
pub const MARGIN_MM: u32 = 50;

/// A zone as the owner draws it, in world mm (x east, y north, origin at
/// the map's bottom-left corner), as ValetudoMap's `no_go_area` and
/// `virtual_wall` entities are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Zone {
    /// An axis-aligned rectangle the body never enters (corners in any
    /// order).
    NoGo {
        /// One corner's x, mm.
        x0_mm: i32,
        /// One corner's y, mm.
        y0_mm: i32,
        /// The opposite corner's x, mm.
        x1_mm: i32,
        /// The opposite corner's y, mm.
        y1_mm: i32,
    },
    /// A line segment the body never crosses or touches.
    Wall {
        /// One end's x, mm.
        ax_mm: i32,
        /// One end's y, mm.
        ay_mm: i32,
        /// The other end's x, mm.
        bx_mm: i32,
        /// The other end's y, mm.
        by_mm: i32,
    },
}

/// Zones that could not be set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ZoneError {
    /// More zones than [`MAX_ZONES`]: none is set (a rule silently dropped
    /// would let the robot into a room its owner closed).
    TooMany {
        /// Zones given.
        given: u32,
        /// Zones a map holds.
        capacity: u32,
    },
}

impl core::fmt::Display for ZoneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            ZoneError::TooMany { given, capacity } => write!(
                f,
                "{given} no-go zones and virtual walls given, at most {capacity} are kept"
            ),
        }
    }
}

/// One zone on the cells: a box of cells (corners inclusive; for a wall,
/// the band's bounding box) and, for a wall, the segment (index-space mm)
/// and the distance from it within which a cell's centre is in the band.
#[derive(Clone, Copy, Debug, Default)]
struct CellZone {
    x0: i16,
    y0: i16,
    x1: i16,
    y1: i16,
    /// A virtual wall: its ends, index-space mm; `reach_mm` 0 for a no-go
    /// rectangle.
    seg: (i32, i32, i32, i32),
    reach_mm: i32,
}

/// The zones of one map, on its cells. Empty by default: asking costs
/// one comparison then.
#[derive(Clone, Copy, Debug, Default)]
pub struct Zones {
    zones: [CellZone; MAX_ZONES],
    len: u8,
}

impl Zones {
    /// No zones.
    pub const fn new() -> Self {
        const EMPTY: CellZone = CellZone {
            x0: 0,
            y0: 0,
            x1: -1,
            y1: -1,
            seg: (0, 0, 0, 0),
            reach_mm: 0,
        };
        Self {
            zones: [EMPTY; MAX_ZONES],
            len: 0,
        }
    }

    /// Sets the zones of a map `height_cells` tall with cells of `res_mm`,
    /// each grown by `margin_mm`. All or nothing: on an error the zones
    /// are as they were.
    pub fn set(
        &mut self,
        zones: &[Zone],
        height_cells: u32,
        res_mm: u32,
        margin_mm: u32,
    ) -> Result<(), ZoneError> {
        if zones.len() > MAX_ZONES {
            return Err(ZoneError::TooMany {
                given: zones.len().min(u32::MAX as usize) as u32,
                capacity: MAX_ZONES as u32,
            });
        }
        let (res, m) = (res_mm.max(1) as i64, margin_mm.min(1 << 20) as i64);
        let hmm = height_cells as i64 * res;
        for (slot, z) in self.zones.iter_mut().zip(zones) {
            *slot = cell_zone(z, hmm, res, m);
        }
        self.len = zones.len() as u8;
        Ok(())
    }

    /// How many zones are set.
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// True when no zone is set.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// True when cell (cx, cy) of `res_mm` lies in a zone (its margin
    /// included): the body must not overlap it.
    #[inline]
    pub fn blocks(&self, cx: i32, cy: i32, res_mm: u32) -> bool {
        self.len != 0 && self.blocks_any(cx, cy, res_mm)
    }

    fn blocks_any(&self, cx: i32, cy: i32, res_mm: u32) -> bool {
        let live = self.zones.get(..self.len as usize).unwrap_or(&[]);
        live.iter().any(|z| {
            let inside = cx >= z.x0 as i32 && cx <= z.x1 as i32;
            if !(inside && cy >= z.y0 as i32 && cy <= z.y1 as i32) {
                return false;
            }
            if z.reach_mm == 0 {
                return true;
            }
            let res = res_mm.max(1) as i64;
            let p = (cx as i64 * res + res / 2, cy as i64 * res + res / 2);
            let (ax, ay, bx, by) = z.seg;
            let d2 = seg_dist2(p, (ax as i64, ay as i64), (bx as i64, by as i64));
            d2 <= z.reach_mm as i64 * z.reach_mm as i64
        })
    }
}

/// A zone on the cells of a map `hmm` mm tall with cells of `res` mm,
/// grown by `m` mm.
fn cell_zone(z: &Zone, hmm: i64, res: i64, m: i64) -> CellZone {
    let cell = |v: i64| v.clamp(-1, i16::MAX as i64) as i16;
    // The cells overlapping [lo, hi] (mm) with positive length.
    let span = |lo: i64, hi: i64| (cell(lo.div_euclid(res)), cell((hi - 1).div_euclid(res)));
    match *z {
        Zone::NoGo {
            x0_mm,
            y0_mm,
            x1_mm,
            y1_mm,
        } => {
            let (xa, xb) = (x0_mm.min(x1_mm) as i64, x0_mm.max(x1_mm) as i64);
            let (ya, yb) = (hmm - y0_mm.max(y1_mm) as i64, hmm - y0_mm.min(y1_mm) as i64);
            let (x0, x1) = span(xa - m, xb + m);
            let (y0, y1) = span(ya - m, yb + m);
            CellZone {
                x0,
                y0,
                x1,
                y1,
                ..CellZone::default()
            }
        }
        Zone::Wall {
            ax_mm,
            ay_mm,
            bx_mm,
            by_mm,
        } => {
            // A cell is in the band when its centre is within the margin
            // plus half its diagonal of the segment: every cell the
            // segment passes through is then in it, and a body cannot slip
            // between two cells meeting at a corner.
            let reach = m + (res * 708 + 999) / 1000;
            let (ay, by) = (hmm - ay_mm as i64, hmm - by_mm as i64);
            let (ax, bx) = (ax_mm as i64, bx_mm as i64);
            let (x0, x1) = span(ax.min(bx) - reach, ax.max(bx) + reach + 1);
            let (y0, y1) = span(ay.min(by) - reach, ay.max(by) + reach + 1);
            let mm = |v: i64| v.clamp(-(1 << 30), 1 << 30) as i32;
            CellZone {
                x0,
                y0,
                x1,
                y1,
                seg: (mm(ax), mm(ay), mm(bx), mm(by)),
                reach_mm: mm(reach).max(1),
            }
        }
    }
}

/// Squared distance (mm²) from point `p` to the segment `a`–`b`.
pub fn seg_dist2(p: (i64, i64), a: (i64, i64), b: (i64, i64)) -> i64 {
    let (ux, uy) = (b.0 - a.0, b.1 - a.1);
    let (qx, qy) = (p.0 - a.0, p.1 - a.1);
    let len2 = ux * ux + uy * uy;
    let dot = qx * ux + qy * uy;
    let (dx, dy) = if len2 == 0 || dot <= 0 {
        (qx, qy)
    } else if dot >= len2 {
        (p.0 - b.0, p.1 - b.1)
    } else {
        // The foot of the perpendicular, rounded: within a millimetre.
        (qx - ux * dot / len2, qy - uy * dot / len2)
    };
    dx * dx + dy * dy
}

#[cfg(test)]
mod tests {
    use super::*;

    const RES: u32 = 50;
    const H: u32 = 40; // 2 m tall map

    fn zones(z: &[Zone], margin: u32) -> Zones {
        let mut s = Zones::new();
        assert!(s.set(z, H, RES, margin).is_ok());
        s
    }

    #[test]
    fn a_rectangle_blocks_exactly_the_cells_it_overlaps() {
        // World x 100..200, y 1800..1900: index y 100..200.
        let s = zones(
            &[Zone::NoGo {
                x0_mm: 200,
                y0_mm: 1900,
                x1_mm: 100,
                y1_mm: 1800,
            }],
            0,
        );
        for cy in -2..10 {
            for cx in -2..10 {
                let want = (2..=3).contains(&cx) && (2..=3).contains(&cy);
                assert_eq!(s.blocks(cx, cy, RES), want, "({cx},{cy})");
            }
        }
        // A margin of one cell grows it by one cell each way.
        let s = zones(
            &[Zone::NoGo {
                x0_mm: 100,
                y0_mm: 1800,
                x1_mm: 200,
                y1_mm: 1900,
            }],
            50,
        );
        assert!(s.blocks(1, 1, RES) && s.blocks(4, 4, RES) && !s.blocks(5, 4, RES));
    }

    #[test]
    fn a_diagonal_wall_leaves_no_gap_between_its_cells() {
        let s = zones(
            &[Zone::Wall {
                ax_mm: 0,
                ay_mm: 2000,
                bx_mm: 1000,
                by_mm: 1000,
            }],
            0,
        );
        // Every cell on the line's path is blocked, and from every blocked
        // cell the next one along is a 4-neighbour or shares an edge run:
        // walk the 4-connected cells crossing x = k and check each column
        // has a blocked cell adjacent (4-way) to the previous column's.
        for cx in 0..20 {
            let cy = cx; // the line y_index = x
            assert!(s.blocks(cx, cy, RES), "({cx},{cy})");
            assert!(s.blocks(cx + 1, cy, RES) || s.blocks(cx, cy + 1, RES));
        }
        assert!(!s.blocks(5, 9, RES) && !s.blocks(9, 5, RES));
    }

    #[test]
    fn too_many_zones_are_refused_whole() {
        let mut s = zones(
            &[Zone::NoGo {
                x0_mm: 0,
                y0_mm: 0,
                x1_mm: 100,
                y1_mm: 100,
            }],
            0,
        );
        let many = [Zone::Wall {
            ax_mm: 0,
            ay_mm: 0,
            bx_mm: 10,
            by_mm: 0,
        }; MAX_ZONES + 1];
        assert_eq!(
            s.set(&many, H, RES, 0),
            Err(ZoneError::TooMany {
                given: MAX_ZONES as u32 + 1,
                capacity: MAX_ZONES as u32
            })
        );
        assert_eq!(s.len(), 1);
        assert!(s.blocks(0, H as i32 - 1, RES));
    }

    #[test]
    fn no_zone_blocks_nothing() {
        let s = Zones::new();
        assert!(s.is_empty() && !s.blocks(0, 0, RES));
    }
}
