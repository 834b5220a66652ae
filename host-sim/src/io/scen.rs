//! MovingAI `.scen` scenario files and running them.

use std::path::Path;
use std::time::Instant;

use robovac::search::prune::prune;
use robovac::{Algo, Cell};

use crate::capacity::{new_grid, HostGrid};
use crate::io::maps::{MapData, MapError};
use crate::report::metrics::{median, polyline_length};

/// One scenario problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// Difficulty bucket.
    pub bucket: u32,
    /// Map file named by the scenario.
    pub map: String,
    /// Map width stated by the scenario.
    pub width: u32,
    /// Map height stated by the scenario.
    pub height: u32,
    /// Start cell.
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// The recorded optimal octile cost.
    pub optimal: f64,
}

/// Parses a `.scen` file (`version 1`, then tab-separated problems).
pub fn parse_scen(path: &Path, bytes: &[u8]) -> Result<Vec<Problem>, MapError> {
    let e = |m: String| MapError(format!("{}: {m}", path.display()));
    let t = std::str::from_utf8(bytes).map_err(|_| e("not a text file".into()))?;
    let mut lines = t.lines().enumerate();
    match lines.next() {
        Some((_, l)) if l.trim().starts_with("version") => {}
        _ => return Err(e("missing 'version' header line".into())),
    }
    let mut out = Vec::new();
    for (n, line) in lines {
        let line = line.trim_end_matches('\r');
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split('\t').collect();
        let f: Vec<&str> = if f.len() == 9 {
            f
        } else {
            line.split_whitespace().collect()
        };
        if f.len() != 9 {
            return Err(e(format!(
                "line {}: expected 9 fields, found {}",
                n + 1,
                f.len()
            )));
        }
        let int = |s: &str, what: &str| -> Result<u32, MapError> {
            s.parse::<u32>()
                .map_err(|_| e(format!("line {}: {what} {s:?} is not a number", n + 1)))
        };
        let cell = |x: &str, y: &str| -> Result<Cell, MapError> {
            let (x, y) = (int(x, "x")?, int(y, "y")?);
            Cell::from_xy(x as i32, y as i32)
                .ok_or_else(|| e(format!("line {}: coordinate out of range", n + 1)))
        };
        let optimal: f64 = f[8]
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| {
                e(format!(
                    "line {}: optimal {:?} is not a number",
                    n + 1,
                    f[8]
                ))
            })?;
        out.push(Problem {
            bucket: int(f[0], "bucket")?,
            map: f[1].to_string(),
            width: int(f[2], "width")?,
            height: int(f[3], "height")?,
            start: cell(f[4], f[5])?,
            goal: cell(f[6], f[7])?,
            optimal,
        });
    }
    Ok(out)
}

/// The outcome of running a scenario.
#[derive(Clone, Debug, Default)]
pub struct ScenReport {
    /// Algorithm name.
    pub algo: String,
    /// Problems in the file.
    pub problems: usize,
    /// Problems for which a path was found.
    pub solved: usize,
    /// Problems whose cost differs from the optimum by more than 1e-3.
    pub optimal_mismatches: usize,
    /// Mean of found cost / optimal cost (problems with optimum > 0).
    pub mean_cost_ratio: f64,
    /// Mean nodes expanded.
    pub mean_nodes_expanded: f64,
    /// Median µs per query (search plus reading the path out).
    pub median_query_us: f64,
    /// Mean cost after pruning.
    pub mean_pruned_cost: f64,
    /// The first few mismatches, for the report.
    pub mismatch_examples: Vec<String>,
}

/// Algorithm name as used on the command line.
pub fn algo_name(a: Algo) -> &'static str {
    match a {
        Algo::AStar => "astar",
        Algo::Oha => "oha",
        Algo::Theta => "theta",
        Algo::AStarOctile => "astar-octile",
        Algo::Bfs => "bfs",
        Algo::Dfs => "dfs",
        Algo::Jps => "jps",
    }
}

/// Problem `k` (from 0) was made for a map of `map`'s size.
pub fn check_size(map: &MapData, k: usize, p: &Problem) -> Result<(), MapError> {
    if p.width == map.width && p.height == map.height {
        return Ok(());
    }
    Err(MapError(format!(
        "problem {}: scenario says {}x{}, map is {}x{}",
        k + 1,
        p.width,
        p.height,
        map.width,
        map.height
    )))
}

/// Runs every problem on `map` with `plan`, which writes a path into its
/// buffer and gives its length and the nodes expanded, or says why there is
/// none; `name` names the engine in the report.
pub fn run_scen(
    map: &MapData,
    problems: &[Problem],
    name: &str,
    mut plan: impl FnMut(&HostGrid, &Problem, &mut [Cell]) -> Result<(usize, u32), String>,
) -> Result<ScenReport, MapError> {
    let mut grid = new_grid();
    map.to_grid(&mut *grid)?;
    let mut path = vec![Cell::default(); grid.cells()];
    let mut rep = ScenReport {
        algo: name.into(),
        problems: problems.len(),
        ..Default::default()
    };
    let (mut ratios, mut nodes, mut times, mut pruned) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (k, p) in problems.iter().enumerate() {
        check_size(map, k, p)?;
        let t0 = Instant::now();
        let res = plan(&grid, p, &mut path);
        times.push(t0.elapsed().as_secs_f64() * 1e6);
        let (n, expanded) = match res {
            Ok(r) => r,
            Err(why) => {
                // An unsolved problem differs from its recorded optimum too.
                rep.optimal_mismatches += 1;
                if rep.mismatch_examples.len() < 5 {
                    rep.mismatch_examples
                        .push(format!("problem {}: {why}", k + 1));
                }
                continue;
            }
        };
        rep.solved += 1;
        let cost = polyline_length(&path[..n]);
        nodes.push(expanded as f64);
        if (cost - p.optimal).abs() > 1e-3 {
            rep.optimal_mismatches += 1;
            if rep.mismatch_examples.len() < 5 {
                rep.mismatch_examples.push(format!(
                    "problem {}: ({},{})->({},{}) cost {cost:.6}, optimal {:.6}",
                    k + 1,
                    p.start.x,
                    p.start.y,
                    p.goal.x,
                    p.goal.y,
                    p.optimal
                ));
            }
        }
        if p.optimal > 0.0 {
            ratios.push(cost / p.optimal);
        }
        let m = prune(&*grid, &mut path[..n]);
        pruned.push(polyline_length(&path[..m]));
    }
    rep.mean_cost_ratio = crate::report::metrics::mean(&ratios);
    rep.mean_nodes_expanded = crate::report::metrics::mean(&nodes);
    rep.median_query_us = median(&mut times);
    rep.mean_pruned_cost = crate::report::metrics::mean(&pruned);
    Ok(rep)
}
