//! `bench replan` (issue 13): D* Lite against A* searched again from
//! nothing, on a map that changes while the robot walks.
//!
//! **Protocol** (ours; the seeds give none): for each MovingAI problem the
//! robot plans from start to goal and walks its path. After every `every`
//! cells walked, an obstacle of `side` × `side` cells (3 × 3 by default:
//! a person, a chair) appears
//! centred `ahead` cells further along its path, where its lidar would see
//! it; the robot's own cell and the goal are never blocked, and obstacles
//! stay. Each time, both engines plan from where the robot stands on the
//! changed map: D* Lite repairs its previous search
//! ([`robovac::search::dstar_lite`]), A* octile searches from nothing. Both
//! costs are checked equal (both are optimal on the same graph). The robot
//! walks on along D* Lite's path. A problem ends at the goal, when no path
//! is left, or after `changes` obstacles. The engines alternate, so drift
//! in the machine's speed hits both alike.

use std::time::Instant;

use robovac::search::dstar_lite::DStarLite;
use robovac::{Algo, Cell};

use crate::capacity::{new_grid, new_search, HostGrid, HOST_CELLS, HOST_OPEN};
use crate::io::maps::{MapData, MapError};
use crate::io::scen::{check_size, Problem};
use crate::report::metrics::median;

/// The host's D* Lite.
pub type HostDStar = DStarLite<HOST_CELLS, HOST_OPEN>;

/// How the map changes.
#[derive(Clone, Copy, Debug)]
pub struct Changes {
    /// Cells walked between two obstacles.
    pub every: usize,
    /// How far along the path an obstacle appears, cells.
    pub ahead: usize,
    /// Obstacles per problem at most.
    pub changes: usize,
    /// An obstacle's side, cells (odd: it is centred on a path cell).
    pub side: usize,
}

/// The figures of one engine over every replan.
#[derive(Clone, Debug, Default)]
pub struct EngineReplans {
    /// Nodes expanded per replan.
    pub nodes: Vec<u32>,
    /// µs per replan.
    pub us: Vec<f64>,
}

impl EngineReplans {
    /// Mean nodes per replan.
    pub fn mean_nodes(&self) -> f64 {
        self.nodes.iter().map(|&n| n as f64).sum::<f64>() / self.nodes.len().max(1) as f64
    }

    /// Median µs per replan.
    pub fn median_us(&mut self) -> f64 {
        median(&mut self.us)
    }
}

/// The comparison.
#[derive(Clone, Debug, Default)]
pub struct ReplanReport {
    /// Problems run.
    pub problems: usize,
    /// The first plans (D* Lite's initial search), for scale.
    pub first: EngineReplans,
    /// D* Lite's repairs.
    pub dstar: EngineReplans,
    /// A* octile from nothing, at the same moments.
    pub astar: EngineReplans,
    /// Replans whose two costs differ (must be 0).
    pub mismatches: usize,
    /// How the problems ended: at the goal, cut off from it by an
    /// obstacle (both engines agreeing there is no path), or with every
    /// obstacle placed.
    pub ended: [usize; 3],
}

/// How one problem ended (the index into [`ReplanReport::ended`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ended {
    /// The robot reached the goal.
    AtGoal = 0,
    /// An obstacle cut the goal off.
    CutOff = 1,
    /// `changes` obstacles were placed.
    AllChanges = 2,
}

/// Runs every problem.
pub fn run_replan(
    map: &MapData,
    problems: &[Problem],
    how: Changes,
) -> Result<ReplanReport, MapError> {
    let mut rep = ReplanReport {
        problems: problems.len(),
        ..Default::default()
    };
    let mut grid = new_grid();
    let mut dstar = new_dstar();
    let mut astar = new_search();
    let mut path = vec![Cell::default(); HOST_CELLS];
    for (k, p) in problems.iter().enumerate() {
        check_size(map, k, p)?;
        map.to_grid(&mut *grid)?;
        let t0 = Instant::now();
        let first = dstar
            .begin(&*grid, p.start, p.goal)
            .and_then(|_| dstar.compute(&*grid));
        let Ok(first) = first else { continue };
        rep.first.us.push(t0.elapsed().as_secs_f64() * 1e6);
        rep.first.nodes.push(first.nodes_expanded);
        let end = walk(
            &mut grid, &mut dstar, &mut astar, &mut path, p.goal, how, &mut rep,
        );
        rep.ended[end as usize] += 1;
    }
    Ok(rep)
}

/// Walks one problem to its end.
fn walk(
    grid: &mut HostGrid,
    dstar: &mut HostDStar,
    astar: &mut crate::capacity::HostSearch,
    path: &mut [Cell],
    goal: Cell,
    how: Changes,
    rep: &mut ReplanReport,
) -> Ended {
    for _ in 0..how.changes {
        let Ok(n) = dstar.write_path(grid, path) else {
            return Ended::CutOff;
        };
        let at = path[how.every.min(n - 1)];
        let blob = blob_cells(grid, &path[..n], how, at, goal);
        if blob.is_empty() || dstar.move_to(grid, at).is_err() {
            return Ended::AtGoal; // too near the goal for another obstacle
        }
        for c in &blob {
            let _ = grid.set_obstacle(c.x as i32, c.y as i32, true);
        }
        let t0 = Instant::now();
        let repaired = dstar
            .cells_changed(grid, &blob)
            .and_then(|_| dstar.compute(grid));
        let d_us = t0.elapsed().as_secs_f64() * 1e6;
        let t0 = Instant::now();
        let fresh = astar.search(grid, at, &[goal], Algo::AStarOctile);
        let a_us = t0.elapsed().as_secs_f64() * 1e6;
        match (repaired, fresh) {
            (Ok(d), Ok(a)) => {
                rep.dstar.nodes.push(d.nodes_expanded);
                rep.dstar.us.push(d_us);
                rep.astar.nodes.push(a.nodes_expanded);
                rep.astar.us.push(a_us);
                rep.mismatches += usize::from(d.cost != a.cost);
            }
            (Err(_), Err(_)) => return Ended::CutOff,
            _ => {
                rep.mismatches += 1;
                return Ended::CutOff;
            }
        }
    }
    Ended::AllChanges
}

/// The free cells of the `side` × `side` square centred `ahead` cells past `at` on
/// the path, less the robot's cell and the goal.
fn blob_cells(grid: &HostGrid, path: &[Cell], how: Changes, at: Cell, goal: Cell) -> Vec<Cell> {
    let Some(&centre) = path.get(how.every + how.ahead) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let r = (how.side / 2) as i32;
    for dy in -r..=r {
        for dx in -r..=r {
            let (x, y) = (centre.x as i32 + dx, centre.y as i32 + dy);
            let Some(c) = Cell::from_xy(x, y) else {
                continue;
            };
            if grid.is_free(x, y) && c != at && c != goal {
                out.push(c);
            }
        }
    }
    out
}

/// A host D* Lite on the heap, without building it on the stack.
pub fn new_dstar() -> Box<HostDStar> {
    let b = Box::<HostDStar>::new_zeroed();
    // SAFETY: `DStarLite` consists only of integers, arrays and structs of
    // them, a bool, and the open list's `#[repr(u8)]` order whose
    // discriminant 0 is a variant; its documentation guarantees that
    // all-zero bytes are a valid idle state.
    unsafe { b.assume_init() }
}
