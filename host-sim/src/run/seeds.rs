//! `bench seeds`: the seeds' own experiments, reproduced as far as their
//! text describes them, beside the numbers they report.
//!
//! The seeds draw their maps in figures we do not have, so each protocol is
//! incomplete; the maps in `maps/seeds/` are ours, drawn after the text:
//! - **seed 003** (§4): a 20 × 20 grid, the robot starting at cell (1, 20)
//!   (1-based, the bottom-left corner), coverage = covered ÷ (n² −
//!   obstacles) and repetition = repeated cells ÷ (n² − obstacles); our map
//!   has one U-shaped obstacle and three convex ones; the seed's own
//!   planner is our `regions`, in our reading of its decomposition.
//! - **seed 001** (§5.1, §5.2): a 400 × 400 cm room, a 33 cm robot as one
//!   cell (12 × 12), starting top-left; metrics: sub-regions, backtracking
//!   length, first-pass coverage (covered before the first transit) and
//!   repetition. Its Table 1 is an image, not in our copy of the text, so
//!   no paper figure stands beside ours. The online run (unknown mode) is
//!   the mission in the same room at 0.11 m cells.
//! - **seed 002** (§4): corridors of 230 m² with people walking; 98.3 %
//!   coverage and 2.6 % repetition with two avoidance events. Ours: the
//!   mission on a 230 m² corridor ring with a cross corridor, two people,
//!   known map, the template planner (and B-OHA* beside it).

use std::path::Path;

use robovac::coverage::PlannerKind;
use robovac::grid::los::supercover;
use robovac::mission::MapMode;

use crate::io::maps::{parse_ascii, MapData};
use crate::run::mission::{run_mission, MissionOptions};
use crate::run::plan::{plan, Plan};
use crate::sim::config::Noise;

/// Seed 003's map (ours, after §4).
pub const SEED003_MAP: &str = include_str!("../../../maps/seeds/seed003_20x20.txt");
/// Seed 001's room (ours, after §5.2).
pub const SEED001_MAP: &str = include_str!("../../../maps/seeds/seed001_room12.txt");
/// Seed 002's corridors (ours, after §4), 0.1 m cells.
pub const SEED002_MAP: &str = include_str!("../../../maps/seeds/seed002_corridors.txt");

/// A built-in map by name.
pub fn map(name: &str, text: &str) -> Result<MapData, String> {
    parse_ascii(Path::new(name), text.as_bytes()).map_err(|e| e.to_string())
}

/// A plan's figures in the seeds' terms.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SeedFigures {
    /// The planner.
    pub planner: &'static str,
    /// Covered ÷ free cells.
    pub coverage: f64,
    /// Cells visited more than once ÷ free cells (seeds 001 and 003).
    pub repetition: f64,
    /// Cover segments (seed 001's sub-regions).
    pub sub_regions: u32,
    /// Transit length, cells.
    pub backtrack_cells: f64,
    /// Cells covered before the first transit ÷ free cells.
    pub first_pass: f64,
}

/// Counts each free cell's visits along a plan (every segment's cells, its
/// first cell, the previous segment's last, not counted twice).
fn visits(map: &MapData, p: &Plan) -> Vec<u32> {
    let w = map.width as i32;
    let mut n = vec![0u32; (map.width * map.height) as usize];
    let mut at = p.start.xy();
    n[(at.1 * w + at.0) as usize] += 1;
    for m in &p.moves {
        let to = m.to.xy();
        supercover(at, to, |x, y| {
            if (x, y) != at && !map.is_blocked(x, y) {
                n[(y * w + x) as usize] += 1;
            }
            true
        });
        at = to;
    }
    n
}

/// The seeds' figures of `kind`'s plan of `map` from `start`.
pub fn figures(
    map: &MapData,
    kind: PlannerKind,
    start: robovac::Cell,
) -> Result<SeedFigures, String> {
    let p = plan(map, kind, Some(start))?;
    let free = map.blocked.iter().filter(|b| !**b).count().max(1) as f64;
    let v = visits(map, &p);
    let covered = v.iter().filter(|&&k| k > 0).count() as f64;
    let repeated = v.iter().filter(|&&k| k > 1).count() as f64;
    let first_transit = p
        .moves
        .iter()
        .position(|m| m.kind == robovac::verify::metrics::SegmentKind::Transit)
        .unwrap_or(p.moves.len());
    let first_pass = 1 + first_transit; // the start, then one cell a move
    let cells = |c: u64| c as f64 / robovac::math::cost::COST_PER_CELL as f64;
    Ok(SeedFigures {
        planner: kind.name(),
        coverage: covered / free,
        repetition: repeated / free,
        sub_regions: p.metrics.segments,
        backtrack_cells: cells(p.metrics.backtrack_path_cost),
        first_pass: first_pass as f64 / free,
    })
}

/// Seed 001's room at the mission's scale: each 33 cm cell as 3 × 3 cells
/// of 0.11 m, inside a wall.
pub fn room_for_mission(room: &MapData) -> MapData {
    let k = 3u32;
    let (w, h) = (room.width * k + 2, room.height * k + 2);
    let mut blocked = vec![true; (w * h) as usize];
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let (rx, ry) = (((x - 1) / k) as i32, ((y - 1) / k) as i32);
            blocked[(y * w + x) as usize] = room.is_blocked(rx, ry);
        }
    }
    MapData {
        width: w,
        height: h,
        blocked,
        cell_m: Some(0.11),
        dock: None,
        extras: None,
    }
}

/// One mission of the seeds' experiments: known or unknown map, people,
/// planner, seed.
pub fn mission(
    map: &MapData,
    mode: MapMode,
    people: usize,
    kind: PlannerKind,
    seed: u64,
) -> Result<crate::run::mission::MissionReport, String> {
    let mut o = MissionOptions::new(map.clone(), mode, people, Noise::None, seed);
    o.kind = kind;
    run_mission(&o, |_, _, _| {}).map(|(r, _, _)| r)
}
