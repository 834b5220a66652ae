//! Arguments and helpers the commands share.

use std::path::{Path, PathBuf};

use clap::ValueEnum;
use host_sim::io::maps::{load_map, LoadOptions, MapData};
use host_sim::run::engines::Engine;
use robovac::{Algo, Cell};

#[derive(Clone, Copy, ValueEnum)]
pub enum NoiseArg {
    None,
    Realistic,
    Harsh,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum ModeArg {
    Known,
    Unknown,
}

/// The local planner that steers an avoidance.
#[derive(Clone, Copy, ValueEnum)]
pub enum LocalArg {
    /// The dynamic window (seed 002's; the default).
    Dwa,
    /// The artificial potential field (seed 004's), for comparison: its
    /// local minima are counted and logged.
    Apf,
}

impl From<LocalArg> for robovac::mission::LocalPlanner {
    fn from(l: LocalArg) -> Self {
        match l {
            LocalArg::Dwa => Self::Dwa,
            LocalArg::Apf => Self::Apf,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub enum AlgoArg {
    /// A* with the Euclidean heuristic (seed 000's Table 1).
    Astar,
    /// A* with the integer octile heuristic (optimal, fastest).
    AstarOctile,
    /// Jump point search: A* octile's costs, only the jump points pushed
    /// (optimal, fastest on open rooms).
    Jps,
    /// Breadth-first search (fewest moves; a baseline).
    Bfs,
    /// Depth-first search (some path; a baseline).
    Dfs,
    Oha,
    Theta,
    /// D* Lite (one plan here; `bench replan` repairs it as the map changes).
    DstarLite,
    /// The artificial potential field (a walk downhill; it may be held at a
    /// local minimum).
    Apf,
}

impl AlgoArg {
    /// The engine that runs it.
    pub fn engine(self) -> Engine {
        match self {
            AlgoArg::Astar => Engine::BestFirst(Algo::AStar),
            AlgoArg::AstarOctile => Engine::BestFirst(Algo::AStarOctile),
            AlgoArg::Jps => Engine::BestFirst(Algo::Jps),
            AlgoArg::Bfs => Engine::BestFirst(Algo::Bfs),
            AlgoArg::Dfs => Engine::BestFirst(Algo::Dfs),
            AlgoArg::Oha => Engine::BestFirst(Algo::Oha),
            AlgoArg::Theta => Engine::BestFirst(Algo::Theta),
            AlgoArg::DstarLite => Engine::DStarLite,
            AlgoArg::Apf => Engine::Apf,
        }
    }
}

#[derive(clap::Args)]
pub struct MapArgs {
    /// Map file: .map (MovingAI), .yaml (ROS), .png, .pgm, or ASCII.
    #[arg(long)]
    pub map: PathBuf,
    /// Resample image maps to cells of this size (metres).
    #[arg(long)]
    pub cell: Option<f64>,
    /// Metres per pixel of a PNG map (default 0.05).
    #[arg(long)]
    pub resolution: Option<f64>,
}

impl MapArgs {
    pub fn load(&self) -> Result<MapData, String> {
        load_map(
            &self.map,
            LoadOptions {
                cell_m: self.cell,
                png_resolution_m: self.resolution,
            },
        )
        .map_err(|e| e.to_string())
    }
}

pub fn parse_point(s: &str) -> Result<(f64, f64), String> {
    let (x, y) = s
        .split_once(',')
        .ok_or_else(|| format!("{s:?} is not X,Y"))?;
    let p = |v: &str| {
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|f| f.is_finite() && *f >= 0.0)
            .ok_or_else(|| format!("{v:?} is not a non-negative number"))
    };
    Ok((p(x)?, p(y)?))
}

pub fn parse_cell(s: &str) -> Result<Cell, String> {
    let (x, y) = s
        .split_once(',')
        .ok_or_else(|| format!("{s:?} is not X,Y"))?;
    let x: u16 = x
        .trim()
        .parse()
        .map_err(|_| format!("{x:?} is not a cell column"))?;
    let y: u16 = y
        .trim()
        .parse()
        .map_err(|_| format!("{y:?} is not a cell row"))?;
    Ok(Cell::new(x, y))
}

pub fn write_file(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

impl From<NoiseArg> for host_sim::sim::robot::Noise {
    fn from(n: NoiseArg) -> Self {
        match n {
            NoiseArg::None => host_sim::sim::robot::Noise::None,
            NoiseArg::Realistic => host_sim::sim::robot::Noise::Realistic,
            NoiseArg::Harsh => host_sim::sim::robot::Noise::Harsh,
        }
    }
}

/// A floor for the simulated world: images keep their own resolution (PNG,
/// PGM, ROS YAML); ASCII and MovingAI maps take --cell (default 0.1 m).
pub fn load_world_map(args: &MapArgs) -> Result<(MapData, f64), String> {
    let map = load_map(
        &args.map,
        LoadOptions {
            cell_m: None,
            png_resolution_m: args.resolution,
        },
    )
    .map_err(|e| e.to_string())?;
    let cell_m = map.cell_m.or(args.cell).unwrap_or(0.1);
    if !(cell_m.is_finite() && cell_m > 0.0) {
        return Err("--cell must be a positive number of metres".into());
    }
    Ok((map, cell_m))
}

impl From<ModeArg> for robovac::mission::MapMode {
    fn from(m: ModeArg) -> Self {
        match m {
            ModeArg::Known => robovac::mission::MapMode::Known,
            ModeArg::Unknown => robovac::mission::MapMode::Unknown,
        }
    }
}
