//! Benchmarks that reproduce the papers' protocols.

use std::time::Instant;

use robovac::maps::{table1_instance, RandomMap, SplitMix64};
use robovac::prune::prune;
use robovac::{Algo, Cell};

use crate::metrics::{mean, polyline_length};
use crate::state::{new_grid, new_search};

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
/// [`robovac::maps::TABLE1_MAP`]) with a reachable corner-to-corner pair
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
