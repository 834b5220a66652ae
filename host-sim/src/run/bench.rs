//! Benchmarks that reproduce the papers' protocols.

use std::time::Instant;

use robovac::grid::maps::{table1_instance, RandomMap, SplitMix64};
use robovac::search::prune::prune;
use robovac::{Algo, Cell};

use crate::capacity::{new_grid, new_search};
use crate::report::metrics::{mean, polyline_length};

/// One algorithm's row of Table 1.
#[derive(Clone, Debug, Default)]
pub struct Table1Row {
    /// Algorithm name.
    pub algo: &'static str,
    /// Mean µs per query (search and path read-out; OHA* also its pruning).
    pub mean_time_us: f64,
    /// Mean path cost in cells as the paper reports it: A* unpruned
    /// 8-connected, Theta* its any-angle path, OHA* after pruning.
    pub mean_cost: f64,
    /// Mean cost before pruning.
    pub mean_cost_unpruned: f64,
    /// Mean cost after pruning (Algorithm 1).
    pub mean_cost_pruned: f64,
    /// Mean nodes expanded.
    pub mean_nodes: f64,
    /// The paper's run time (s), cost and nodes.
    pub paper: (f64, f64, f64),
}

/// The paper's Table 1 (run time s, path cost, nodes searched).
pub const PAPER_TABLE1: [(&str, Algo, (f64, f64, f64)); 3] = [
    ("astar", Algo::AStar, (0.25, 120.94, 1267.55)),
    ("theta", Algo::Theta, (0.49, 115.84, 477.01)),
    ("oha", Algo::Oha, (0.22, 115.78, 659.45)),
];

/// Runs seed 000's Table 1 protocol: `runs` random 100 × 50 maps (see
/// [`robovac::grid::maps::TABLE1_MAP`]) with a reachable corner-to-corner pair
/// each; every algorithm gets the same maps and pairs.
pub fn table1(
    runs: usize,
    seed: u64,
    map: RandomMap,
    corner: u32,
    mut progress: impl FnMut(usize, usize),
) -> Vec<Table1Row> {
    let mut grid = new_grid();
    let mut state = new_search();
    let mut rng = SplitMix64::new(seed);
    let mut path = vec![Cell::default(); (map.width * map.height) as usize];
    let mut acc: Vec<[Vec<f64>; 4]> =
        vec![Default::default(), Default::default(), Default::default()];
    let mut done = 0;
    while done < runs {
        let Ok(Some((s, g))) = table1_instance(&mut *grid, &mut rng, map, corner) else {
            continue;
        };
        if state.search(&*grid, s, &[g], Algo::AStar).is_err() {
            continue; // unreachable pair: draw a new map
        }
        for (k, (_, algo, _)) in PAPER_TABLE1.iter().enumerate() {
            let t0 = Instant::now();
            let Ok(stats) = state.search(&*grid, s, &[g], *algo) else {
                continue;
            };
            let Ok(n) = state.write_path(&mut path) else {
                continue;
            };
            let unpruned = polyline_length(&path[..n]);
            let m = prune(&*grid, &mut path[..n]);
            let dt = t0.elapsed().as_secs_f64() * 1e6;
            let pruned = polyline_length(&path[..m]);
            let [t, c, p, nodes] = &mut acc[k];
            t.push(dt);
            c.push(unpruned);
            p.push(pruned);
            nodes.push(stats.nodes_expanded as f64);
        }
        done += 1;
        progress(done, runs);
    }
    PAPER_TABLE1
        .iter()
        .zip(acc.iter())
        .map(|((name, algo, paper), [t, c, p, n])| {
            let (mc, mp) = (mean(c), mean(p));
            Table1Row {
                algo: name,
                mean_time_us: mean(t),
                mean_cost: if *algo == Algo::Oha { mp } else { mc },
                mean_cost_unpruned: mc,
                mean_cost_pruned: mp,
                mean_nodes: mean(n),
                paper: *paper,
            }
        })
        .collect()
}

/// Metric names of Table 2, in the paper's order, with the paper's values
/// per column (BA*, B-Theta*, B-OHA*) × (50×30, 30×50).
pub const PAPER_TABLE2: [(&str, [f64; 6]); 6] = [
    (
        "coverage_path_length",
        [1200.01, 1201.99, 1199.90, 1202.00, 1202.40, 1204.59],
    ),
    ("segments", [38.30, 39.38, 38.37, 39.32, 31.89, 31.85]),
    ("turns", [176.07, 203.04, 177.40, 203.85, 173.67, 172.74]),
    (
        "backtrack_path_length",
        [216.04, 223.03, 205.81, 212.36, 201.26, 200.93],
    ),
    (
        "backtrack_points_total",
        [3885.12, 3750.42, 3865.24, 3692.57, 699.12, 701.00],
    ),
    ("time_s", [0.10, 0.10, 0.15, 0.15, 0.07, 0.07]),
];

/// The paper's value for a metric, planner and size (None for our variant).
pub fn paper_table2(
    metric: &str,
    planner: robovac::coverage::PlannerKind,
    wide: bool,
) -> Option<f64> {
    use robovac::coverage::PlannerKind::*;
    let col = match planner {
        BaStar => 0,
        BTheta => 2,
        BOha => 4,
        BOhaPc | Template | MarkBacktrack | Binn | Wavefront | Stc | Bcd | Regions => return None,
    } + usize::from(wide);
    PAPER_TABLE2
        .iter()
        .find(|(m, _)| *m == metric)
        .map(|(_, v)| v[col])
}

/// Means over the runs of one planner on one map size.
#[derive(Clone, Debug, Default)]
pub struct Table2Agg {
    /// Runs aggregated.
    pub runs: usize,
    /// Sums of each metric (by name), divided at the end.
    pub sums: std::collections::BTreeMap<&'static str, f64>,
    /// Smallest coverage seen.
    pub min_coverage: f64,
    /// Every run's planning time, µs.
    pub times_us: Vec<f64>,
}

impl Table2Agg {
    /// The mean of a metric.
    pub fn mean(&self, k: &str) -> f64 {
        self.sums.get(k).copied().unwrap_or(0.0) / self.runs.max(1) as f64
    }

    fn add(&mut self, p: &crate::run::plan::Plan) {
        let m = &p.metrics;
        let cells = |c: u64| c as f64 / robovac::math::cost::COST_PER_CELL as f64;
        let vals: [(&'static str, f64); 13] = [
            ("coverage", p.coverage()),
            ("repetition", p.repetition()),
            ("reachable_cells", m.reachable_cells as f64),
            ("covered_cells", m.covered_cells as f64),
            ("repeated_cells", m.repeated_cells as f64),
            ("coverage_path_length", cells(m.coverage_path_cost)),
            ("backtrack_path_length", cells(m.backtrack_path_cost)),
            (
                "total_path_length",
                cells(m.coverage_path_cost + m.backtrack_path_cost),
            ),
            ("turns", m.turns as f64),
            (
                "rotation_deg",
                m.rotation_urad as f64 * 1e-6 * 180.0 / std::f64::consts::PI,
            ),
            ("segments", m.segments as f64),
            ("backtrack_points_total", m.backtrack_points_total as f64),
            ("nodes_expanded", m.nodes_expanded as f64),
        ];
        for (k, v) in vals {
            *self.sums.entry(k).or_default() += v;
        }
        *self.sums.entry("time_us").or_default() += p.time_us;
        *self.sums.entry("rescans_with_points").or_default() += p.stats.rescans_with_points as f64;
        *self.sums.entry("backtrack_points_kept").or_default() +=
            p.stats.backtrack_points_kept as f64;
        *self.sums.entry("critical_points").or_default() += p.stats.critical_points as f64;
        *self.sums.entry("abandoned_goals").or_default() += p.stats.abandoned_goals as f64;
        self.min_coverage = if self.runs == 0 {
            p.coverage()
        } else {
            self.min_coverage.min(p.coverage())
        };
        self.times_us.push(p.time_us);
        self.runs += 1;
    }
}

/// Map sizes of Table 2 as (label, width, height): "50×30" is rows ×
/// columns, a tall map; "30×50" is wide.
pub const TABLE2_SIZES: [(&str, u32, u32); 2] = [("50x30", 30, 50), ("30x50", 50, 30)];

/// One generated Table 2 instance: the map and its start.
pub fn table2_instance(
    width: u32,
    height: u32,
    spec: robovac::grid::maps::RandomMap,
    rng: &mut SplitMix64,
) -> Option<(crate::io::maps::MapData, Cell)> {
    let mut grid = Box::new(robovac::Grid::<{ robovac::math::bits::words_for(4096) }>::new());
    let spec = robovac::grid::maps::RandomMap {
        width,
        height,
        ..spec
    };
    robovac::grid::maps::random_obstacles(&mut *grid, spec, rng).ok()?;
    let mut blocked = Vec::with_capacity((width * height) as usize);
    for y in 0..height as i32 {
        for x in 0..width as i32 {
            blocked.push(grid.is_blocked(x, y));
        }
    }
    let map = crate::io::maps::MapData {
        width,
        height,
        blocked,
        cell_m: None,
        ..Default::default()
    };
    let start = map.first_free()?;
    Some((map, start))
}

/// Runs seed 000's Table 2 protocol: `runs` random maps per size, the same
/// maps and starts for every planner. Calls `each` with every plan (for
/// pictures and checks) and `progress` after every map.
pub fn table2(
    runs: usize,
    seed: u64,
    spec: robovac::grid::maps::RandomMap,
    mut each: impl FnMut(&str, usize, &crate::io::maps::MapData, &crate::run::plan::Plan),
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<(&'static str, robovac::coverage::PlannerKind, Table2Agg)>, String> {
    use crate::run::plan::{new_planner, plan_on, SEED000_PLANNERS as ALL_PLANNERS};
    let mut out = Vec::new();
    let mut planners: Vec<_> = ALL_PLANNERS.iter().map(|&k| new_planner(k)).collect();
    let mut grid = crate::capacity::new_grid();
    let mut rng = SplitMix64::new(seed);
    let total = runs * TABLE2_SIZES.len();
    let mut done = 0;
    for (label, w, h) in TABLE2_SIZES {
        let mut aggs: Vec<Table2Agg> = vec![Table2Agg::default(); ALL_PLANNERS.len()];
        for run in 0..runs {
            let (map, start) = loop {
                if let Some(x) = table2_instance(w, h, spec, &mut rng) {
                    break x;
                }
            };
            for (k, planner) in planners.iter_mut().enumerate() {
                map.to_grid(&mut *grid).map_err(|e| e.to_string())?;
                let p = plan_on(&mut grid, planner, start, u32::MAX)?;
                each(label, run, &map, &p);
                aggs[k].add(&p);
            }
            done += 1;
            progress(done, total);
        }
        for (k, agg) in aggs.into_iter().enumerate() {
            out.push((label, ALL_PLANNERS[k], agg));
        }
    }
    Ok(out)
}
