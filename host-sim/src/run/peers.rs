//! `bench peers` (issue 13, search speed): our A* against the
//! general-purpose `pathfinding` crate's A*, side by side in one process on
//! the same MovingAI queries.
//!
//! Both search the same graph: 8-connected, no corner cutting (a diagonal
//! step needs both orthogonal neighbours free), the same integer step costs
//! ([`COST_PER_CELL`], [`COST_DIAGONAL`]) and the same integer octile
//! heuristic. Each query is timed once per engine, the engines alternating
//! query by query so that the machine's drift hits both alike; a query's
//! time includes reading its path out. Both costs are checked against the
//! scenario's optimum.

use std::time::Instant;

use pathfinding::prelude::astar;
use robovac::math::cost::{octile, COST_DIAGONAL, COST_PER_CELL};
use robovac::search::NEIGHBOURS;
use robovac::{Algo, Cell};

use crate::capacity::{new_grid, new_search, HostGrid};
use crate::io::maps::{MapData, MapError};
use crate::io::scen::{check_size, Problem};
use crate::report::metrics::{median, polyline_length};

/// One engine's figures over a scenario.
#[derive(Clone, Debug, Default)]
pub struct EngineFigures {
    /// Its name.
    pub name: String,
    /// Problems solved.
    pub solved: usize,
    /// Problems whose path length differs from the optimum by over 1e-3.
    pub optimal_mismatches: usize,
    /// Median µs per query.
    pub median_us: f64,
    /// Total µs over every query.
    pub total_us: f64,
}

/// The comparison.
#[derive(Clone, Debug, Default)]
pub struct PeersReport {
    /// Problems in the scenario.
    pub problems: usize,
    /// Ours (A* octile), ours with the Euclidean heuristic, ours with jump
    /// points, `pathfinding`.
    pub engines: Vec<EngineFigures>,
    /// `pathfinding`'s median over ours (A* octile).
    pub ratio: f64,
    /// `pathfinding`'s median over ours with jump points (the same graph,
    /// costs and heuristic; only jump points pushed).
    pub jps_ratio: f64,
}

/// The free 8-neighbours of `c` with their step costs, as our search
/// takes them.
fn successors(grid: &HostGrid, c: (i32, i32)) -> Vec<((i32, i32), u32)> {
    let (x, y) = c;
    let mut out = Vec::with_capacity(8);
    for (k, &(dx, dy)) in NEIGHBOURS.iter().enumerate() {
        let (nx, ny) = (x + dx, y + dy);
        if !grid.is_free(nx, ny) {
            continue;
        }
        let diagonal = k % 2 == 1;
        if diagonal && (grid.is_blocked(x + dx, y) || grid.is_blocked(x, y + dy)) {
            continue;
        }
        out.push((
            (nx, ny),
            if diagonal {
                COST_DIAGONAL
            } else {
                COST_PER_CELL
            },
        ));
    }
    out
}

/// Checks a path's length against the problem's optimum.
fn tally(f: &mut EngineFigures, path: Option<&[Cell]>, optimal: f64, us: f64) {
    f.total_us += us;
    if let Some(p) = path {
        f.solved += 1;
        if (polyline_length(p) - optimal).abs() <= 1e-3 {
            return;
        }
    }
    f.optimal_mismatches += 1;
}

/// Runs every problem with each engine.
pub fn run_peers(map: &MapData, problems: &[Problem]) -> Result<PeersReport, MapError> {
    let mut grid = new_grid();
    map.to_grid(&mut *grid)?;
    let mut state = new_search();
    let mut path = vec![Cell::default(); grid.cells()];
    let names = [
        "ours: A* octile",
        "ours: A* Euclidean",
        "ours: JPS",
        "pathfinding 4 A*",
    ];
    let mut figs: Vec<EngineFigures> = names
        .iter()
        .map(|n| EngineFigures {
            name: n.to_string(),
            ..Default::default()
        })
        .collect();
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for (k, p) in problems.iter().enumerate() {
        check_size(map, k, p)?;
        for (e, algo) in [Algo::AStarOctile, Algo::AStar, Algo::Jps]
            .into_iter()
            .enumerate()
        {
            let t0 = Instant::now();
            let n = state
                .search(&*grid, p.start, &[p.goal], algo)
                .and_then(|_| state.write_path(&mut path));
            let us = t0.elapsed().as_secs_f64() * 1e6;
            times[e].push(us);
            tally(&mut figs[e], n.ok().map(|n| &path[..n]), p.optimal, us);
        }
        let (s, g) = (
            (p.start.x as i32, p.start.y as i32),
            (p.goal.x as i32, p.goal.y as i32),
        );
        let t0 = Instant::now();
        let found = astar(
            &s,
            |&c| successors(&grid, c),
            |&(x, y)| octile(g.0 - x, g.1 - y),
            |&c| c == g,
        );
        let us = t0.elapsed().as_secs_f64() * 1e6;
        times[3].push(us);
        let cells: Option<Vec<Cell>> = found.map(|(v, _)| {
            v.iter()
                .map(|&(x, y)| Cell::new(x as u16, y as u16))
                .collect()
        });
        tally(&mut figs[3], cells.as_deref(), p.optimal, us);
    }
    for (f, t) in figs.iter_mut().zip(times.iter_mut()) {
        f.median_us = median(t);
    }
    let peer = figs[3].median_us;
    Ok(PeersReport {
        problems: problems.len(),
        ratio: peer / figs[0].median_us.max(1e-9),
        jps_ratio: peer / figs[2].median_us.max(1e-9),
        engines: figs,
    })
}
