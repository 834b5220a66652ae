//! `bench coverage`: every coverage planner on every map, each plan checked
//! cell by cell by the independent checker ([`robovac::verify::check`]),
//! in the manner of ipa_coverage_planning's evaluation (path length, turns,
//! rotation, computation time, coverage).

use std::path::{Path, PathBuf};

use robovac::coverage::PlannerKind;
use robovac::verify::check::Checker;
use robovac::Cell;

use crate::capacity::{new_grid, HOST_WORDS};
use crate::io::maps::{load_map, LoadOptions, MapData};
use crate::run::plan::{new_planner, plan_on, Plan, PlanMetrics};

/// One plan of the bench.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Row {
    /// The map's file name.
    pub map: String,
    /// The planner's command-line name.
    pub planner: &'static str,
    /// Map size in cells.
    pub cells: (u32, u32),
    /// Cell side, metres (when the map says).
    pub cell_m: Option<f64>,
    /// The start cell.
    pub start: (u16, u16),
    /// The plan's metrics (lengths in cells, rotation in degrees).
    pub metrics: PlanMetrics,
    /// The checker's verdict: every move legal and no reachable cell
    /// missed.
    pub valid: bool,
    /// Reachable cells the checker found missed.
    pub missed_cells: u32,
}

/// The map files of a list of files and directories (directories give
/// their map files, sorted: .map, .json, .png, .pgm, .yaml, .txt).
pub fn map_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    const EXT: [&str; 7] = ["map", "json", "png", "pgm", "yaml", "yml", "txt"];
    let mut out = Vec::new();
    for p in inputs {
        if !p.is_dir() {
            out.push(p.clone());
            continue;
        }
        let rd = std::fs::read_dir(p).map_err(|e| format!("{}: {e}", p.display()))?;
        let mut files: Vec<PathBuf> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|f| {
                let ext = f.extension().and_then(|e| e.to_str()).unwrap_or("");
                EXT.contains(&ext.to_ascii_lowercase().as_str()) && !is_route(f)
            })
            .collect();
        files.sort();
        out.extend(files);
    }
    if out.is_empty() {
        return Err("no map files given".into());
    }
    Ok(out)
}

/// A drive route beside the flats (`*_tour.txt`), not a map.
fn is_route(f: &Path) -> bool {
    f.file_stem()
        .and_then(|s| s.to_str())
        .is_some_and(|s| s.ends_with("_tour"))
}

/// Loads a map for the bench: image and Valetudo maps resampled to `cell_m`
/// (a cell is free when all of it is), grid maps (.map, ASCII) cell for cell.
pub fn load(path: &Path, cell_m: f64) -> Result<MapData, String> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let grid_map = matches!(ext.to_ascii_lowercase().as_str(), "map" | "txt");
    load_map(
        path,
        LoadOptions {
            cell_m: (!grid_map).then_some(cell_m),
            png_resolution_m: None,
        },
    )
    .map_err(|e| e.to_string())
}

/// The start: the first cell, in reading order, of the largest 4-connected
/// free region (a scanned floor has specks of free space outside its walls).
pub fn start_cell(map: &MapData) -> Option<Cell> {
    let (w, h) = (map.width as usize, map.height as usize);
    let mut label = vec![u32::MAX; w * h];
    let (mut best, mut best_size) = (None, 0usize);
    let mut stack = Vec::new();
    for i in 0..w * h {
        if label[i] != u32::MAX || map.blocked.get(i).copied().unwrap_or(true) {
            continue;
        }
        let (mut size, id) = (0usize, i as u32);
        label[i] = id;
        stack.push(i);
        while let Some(j) = stack.pop() {
            size += 1;
            let (x, y) = ((j % w) as i32, (j / w) as i32);
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nx, ny) = (x + dx, y + dy);
                if map.is_blocked(nx, ny) {
                    continue;
                }
                let k = ny as usize * w + nx as usize;
                if label[k] == u32::MAX {
                    label[k] = id;
                    stack.push(k);
                }
            }
        }
        if size > best_size {
            (best, best_size) = (Some(i), size);
        }
    }
    best.and_then(|i| Cell::from_xy((i % w) as i32, (i / w) as i32))
}

/// Plans `map` with each planner from the same start, checks each plan,
/// and calls `each` with the plan (pictures) and `progress` after it.
pub fn bench_map(
    name: &str,
    map: &MapData,
    planners: &[PlannerKind],
    mut each: impl FnMut(&Plan),
) -> Result<Vec<Row>, String> {
    let start = start_cell(map).ok_or_else(|| format!("{name}: no free cell"))?;
    let mut grid = new_grid();
    map.to_grid(&mut *grid)
        .map_err(|e| format!("{name}: {e}"))?;
    let mut rows = Vec::new();
    for &kind in planners {
        let mut planner = new_planner(kind);
        let p = plan_on(&mut grid, &mut planner, start, u32::MAX)
            .map_err(|e| format!("{name}, {}: {e}", kind.name()))?;
        let (valid, missed) = check(&grid, &p, start);
        each(&p);
        rows.push(Row {
            map: name.to_string(),
            planner: kind.name(),
            cells: (map.width, map.height),
            cell_m: map.cell_m,
            start: (start.x, start.y),
            metrics: PlanMetrics::of(&p),
            valid,
            missed_cells: missed,
        });
    }
    Ok(rows)
}

/// The independent checker over a plan's moves: (every move legal, cells
/// missed).
fn check(grid: &crate::capacity::HostGrid, p: &Plan, start: Cell) -> (bool, u32) {
    let mut ck: Box<Checker<HOST_WORDS>> = Box::new(Checker::new());
    if ck.start(grid, start).is_err() {
        return (false, 0);
    }
    let legal = p
        .moves
        .iter()
        .all(|w| ck.push(grid, w.to, w.kind, w.starts_segment).is_ok());
    let c = ck.finish(grid);
    (legal && c.missed_cells == 0, c.missed_cells)
}

/// A metric of the table: its name, how a row gives it, and whether less
/// is better.
pub struct Column {
    /// Header.
    pub name: &'static str,
    /// The value.
    pub get: fn(&Row) -> f64,
    /// Less is better (otherwise more).
    pub lower_is_better: bool,
}

/// The table's metrics.
pub const COLUMNS: [Column; 6] = [
    Column {
        name: "coverage %",
        get: |r| 100.0 * r.metrics.coverage,
        lower_is_better: false,
    },
    Column {
        name: "path cells",
        get: |r| r.metrics.total_path_length,
        lower_is_better: true,
    },
    Column {
        name: "repeated %",
        get: |r| 100.0 * r.metrics.repetition,
        lower_is_better: true,
    },
    Column {
        name: "turns",
        get: |r| r.metrics.turns as f64,
        lower_is_better: true,
    },
    Column {
        name: "rotation deg",
        get: |r| r.metrics.rotation_deg,
        lower_is_better: true,
    },
    Column {
        name: "time ms",
        get: |r| r.metrics.time_us / 1000.0,
        lower_is_better: true,
    },
];

/// The best value of a column over `rows`.
pub fn best(rows: &[&Row], c: &Column) -> f64 {
    let vals = rows.iter().map(|r| (c.get)(r));
    if c.lower_is_better {
        vals.fold(f64::INFINITY, f64::min)
    } else {
        vals.fold(f64::NEG_INFINITY, f64::max)
    }
}
