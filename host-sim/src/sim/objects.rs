//! Things the lidar cannot see (issue 12): objects above or below its
//! scan plane, placed in the twin's world from the command line
//! (`--sofa`, `--crossbar`, `--cable`) or by a test.
//!
//! - **Sofa**: a rectangle the body cannot enter. The lidar's plane
//!   (about 9 cm up on an LD06-topped robot) passes under its frame, so
//!   its beams return from the wall behind; the turret hits the front
//!   rail. Its legs are thin and left out.
//! - **Crossbar**: a chair's bar between two legs, a few cm off the
//!   floor: below the scan plane, at bumper height. A segment the body
//!   cannot cross.
//! - **Cable** (or a rug's edge): a segment on the floor that stalls a
//!   wheel driven forward onto it. The body does not touch it and the
//!   bumper stays open: the robot learns of it only by the stall.
//!
//! Sofas and crossbars are written into the world's grid as blocked
//! cells that rays pass through (as glass is): the twin's physics, its
//! reachable floor and the people keep off them, and the known mode's
//! prior leaves them out (it is the floor plan a lidar would map).
//! Cables are a set of cells apart from the grid.

use crate::sim::floor::Floor;
use crate::sim::robot::Sim;
use crate::sim::world::World;

/// What the object is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LowKind {
    /// A rectangle between opposite corners `a`, `b`.
    Sofa,
    /// A segment from `a` to `b` the body cannot cross.
    Crossbar,
    /// A segment from `a` to `b` that stalls a wheel.
    Cable,
}

/// An object the lidar cannot see, in world metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LowObject {
    /// Its kind.
    pub kind: LowKind,
    /// A corner (sofa) or an end (crossbar, cable), m.
    pub a: (f64, f64),
    /// The opposite corner or the other end, m.
    pub b: (f64, f64),
}

impl LowObject {
    /// The object's name on the command line.
    pub fn name(&self) -> &'static str {
        match self.kind {
            LowKind::Sofa => "sofa",
            LowKind::Crossbar => "crossbar",
            LowKind::Cable => "cable",
        }
    }

    /// Distance (m) from `p` to the object (0 inside a sofa).
    pub fn distance_m(&self, p: (f64, f64)) -> f64 {
        use crate::sim::zones::{rect_distance_m, segment_distance_m};
        match self.kind {
            LowKind::Sofa => rect_distance_m(self.a, self.b, p),
            LowKind::Crossbar | LowKind::Cable => segment_distance_m(self.a, self.b, p),
        }
    }

    /// The world's grid cells (column, row from the top) the object
    /// covers: a sofa every cell its rectangle overlaps, a segment every
    /// cell it passes through.
    pub fn cells(&self, cell_m: f64, height: u32) -> Vec<(i32, i32)> {
        let cell = |x: f64, y: f64| {
            let c = (x / cell_m).floor() as i32;
            (c, height as i32 - 1 - (y / cell_m).floor() as i32)
        };
        let (a, b) = (self.a, self.b);
        let mut out = Vec::new();
        match self.kind {
            LowKind::Sofa => {
                let (c0, r1) = cell(a.0.min(b.0), a.1.min(b.1));
                let (c1, r0) = cell(a.0.max(b.0), a.1.max(b.1));
                for r in r0..=r1 {
                    out.extend((c0..=c1).map(|c| (c, r)));
                }
            }
            LowKind::Crossbar | LowKind::Cable => {
                let len = (b.0 - a.0).hypot(b.1 - a.1);
                let n = ((len / (cell_m / 4.0)).ceil() as usize).max(1);
                for k in 0..=n {
                    let t = k as f64 / n as f64;
                    out.push(cell(a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t));
                }
                out.dedup();
            }
        }
        out
    }
}

/// Puts `objects` into `world`. Refused with a one-line error: an object
/// not wholly on the map, a segment shorter than 5 cm, a sofa with a side
/// under 10 cm.
pub fn place(world: &mut World, objects: &[LowObject]) -> Result<(), String> {
    let (w_m, h_m) = world.size_m();
    for o in objects {
        let on_map = |p: (f64, f64)| p.0 < w_m && p.1 < h_m && p.0 >= 0.0 && p.1 >= 0.0;
        if !on_map(o.a) || !on_map(o.b) {
            return Err(format!(
                "--{}: {:?}–{:?} is not on the map ({w_m:.2} × {h_m:.2} m)",
                o.name(),
                o.a,
                o.b
            ));
        }
        let (dx, dy) = ((o.b.0 - o.a.0).abs(), (o.b.1 - o.a.1).abs());
        let small = match o.kind {
            LowKind::Sofa => dx.min(dy) < 0.1,
            _ => dx.hypot(dy) < 0.05,
        };
        if small {
            return Err(format!("--{}: too small to place", o.name()));
        }
        for (c, r) in o.cells(world.cell_m, world.map.height) {
            match o.kind {
                LowKind::Cable => {
                    world.snag.insert((c, r));
                }
                _ => world.add_low(c, r),
            }
        }
    }
    world.objects.extend_from_slice(objects);
    Ok(())
}

/// The floor within this of an object (m) is where coverage lost around
/// it is measured.
pub const NEAR_M: f64 = 0.5;

/// What the objects cost a mission, measured on the truth.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct ObjectFigures {
    /// Objects placed.
    pub objects: usize,
    /// Contacts with them (the body drove into a sofa or a crossbar):
    /// bumper contacts within 5 cm of the body's rim from one.
    pub contacts: usize,
    /// Times a wheel ran onto a cable and stalled (one lasts until the
    /// wheel is driven backward).
    pub snags: usize,
    /// Time a wheel was held by a cable, s.
    pub snag_time_s: f64,
    /// Reachable floor within [`NEAR_M`] of an object, m².
    pub near_floor_m2: f64,
    /// The share of it swept.
    pub near_coverage: f64,
}

impl ObjectFigures {
    /// The figures at the end of a mission (None: no objects).
    pub fn of(sim: &Sim, floor: &Floor) -> Option<Self> {
        let objects = &sim.world.objects;
        if objects.is_empty() {
            return None;
        }
        let near = |p: (f64, f64), d: f64| objects.iter().any(|o| o.distance_m(p) <= d);
        let rim = sim.cfg.diameter_m / 2.0 + 0.05;
        let contacts = sim
            .collisions
            .iter()
            .filter(|c| c.unseen && near(c.pos, rim))
            .count();
        let (res, w, h) = floor.dims();
        let (mut cells, mut swept) = (0usize, 0usize);
        for y in 0..h {
            for x in 0..w {
                let centre = ((x as f64 + 0.5) * res, (y as f64 + 0.5) * res);
                match floor.state(x, y) {
                    Some(s) if near(centre, NEAR_M) => {
                        cells += 1;
                        swept += s as usize;
                    }
                    _ => {}
                }
            }
        }
        Some(Self {
            objects: objects.len(),
            contacts,
            snags: sim.snags.len(),
            snag_time_s: sim.snag_time_s,
            near_floor_m2: cells as f64 * res * res,
            near_coverage: swept as f64 / cells.max(1) as f64,
        })
    }
}

/// Parses `X0,Y0,X1,Y1` (metres) as an object of `kind`.
pub fn parse(kind: LowKind, s: &str) -> Result<LowObject, String> {
    let (x0, y0, x1, y1) = crate::sim::zones::parse_corners(s)?;
    Ok(LowObject {
        kind,
        a: (x0, y0),
        b: (x1, y1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        let sofa = LowObject {
            kind: LowKind::Sofa,
            a: (1.0, 1.0),
            b: (3.0, 2.0),
        };
        assert_eq!(sofa.distance_m((2.0, 1.5)), 0.0);
        assert!((sofa.distance_m((4.0, 2.0)) - 1.0).abs() < 1e-12);
        let bar = LowObject {
            kind: LowKind::Crossbar,
            a: (0.0, 0.0),
            b: (2.0, 0.0),
        };
        assert!((bar.distance_m((1.0, 0.5)) - 0.5).abs() < 1e-12);
        assert!((bar.distance_m((3.0, 0.0)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn cells_cover_the_shape() {
        let sofa = LowObject {
            kind: LowKind::Sofa,
            a: (0.15, 0.15),
            b: (0.35, 0.25),
        };
        // 10 cm cells, 10 rows: x cells 1..=3, y cells 1..=2 (rows 8, 7).
        let cells = sofa.cells(0.1, 10);
        assert_eq!(cells.len(), 6);
        assert!(cells.contains(&(1, 8)) && cells.contains(&(3, 7)));
        let cable = LowObject {
            kind: LowKind::Cable,
            a: (0.05, 0.05),
            b: (0.95, 0.05),
        };
        let cells = cable.cells(0.1, 10);
        assert_eq!(cells.len(), 10);
        assert!(cells.iter().all(|&(_, r)| r == 9));
    }
}
