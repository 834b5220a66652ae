//! The `host-sim` command line. Bad input ends with a one-line message on
//! stderr and exit code 2, never a backtrace.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand, ValueEnum};
use serde_json::json;

use host_sim::maps::{load_map, LoadOptions, MapData};
use host_sim::metrics::polyline_length;
use host_sim::scen::{algo_name, parse_scen, run_scen};
use host_sim::state::{new_grid, new_search};
use robovac::search::prune::prune;
use robovac::{Algo, Cell};

#[derive(Parser)]
#[command(
    name = "host-sim",
    version,
    about = "robovac host simulator: the firmware core on your PC"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Clone, Copy, ValueEnum)]
enum NoiseArg {
    None,
    Realistic,
}

#[derive(Clone, Copy, ValueEnum)]
enum ModeArg {
    Known,
    Unknown,
}

#[derive(Clone, Copy, ValueEnum)]
enum AlgoArg {
    Astar,
    Oha,
    Theta,
}

impl From<AlgoArg> for Algo {
    fn from(a: AlgoArg) -> Self {
        match a {
            AlgoArg::Astar => Algo::AStar,
            AlgoArg::Oha => Algo::Oha,
            AlgoArg::Theta => Algo::Theta,
        }
    }
}

#[derive(clap::Args)]
struct MapArgs {
    /// Map file: .map (MovingAI), .yaml (ROS), .png, .pgm, or ASCII.
    #[arg(long)]
    map: PathBuf,
    /// Resample image maps to cells of this size (metres).
    #[arg(long)]
    cell: Option<f64>,
    /// Metres per pixel of a PNG map (default 0.05).
    #[arg(long)]
    resolution: Option<f64>,
}

impl MapArgs {
    fn load(&self) -> Result<MapData, String> {
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

#[derive(Subcommand)]
enum Cmd {
    /// A whole cleaning mission on the built-in furnished flat with two people walking; writes demo.svg.
    Demo,
    /// Search one path.
    Search {
        #[command(flatten)]
        map: MapArgs,
        /// Start cell X,Y (column, row from the top).
        #[arg(long, value_parser = parse_cell)]
        from: Cell,
        /// Goal cell X,Y.
        #[arg(long, value_parser = parse_cell)]
        to: Cell,
        #[arg(long, value_enum, default_value = "oha")]
        algo: AlgoArg,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Run every problem of a MovingAI scenario file.
    Scen {
        /// The .scen file.
        scen: PathBuf,
        #[command(flatten)]
        map: MapArgs,
        #[arg(long, value_enum, default_value = "astar")]
        algo: AlgoArg,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Plan a complete coverage of a map.
    Plan {
        #[command(flatten)]
        map: MapArgs,
        /// b-oha, ba, b-theta or b-oha-pc (ours).
        #[arg(long, default_value = "b-oha")]
        planner: String,
        /// Start cell X,Y (default: the first free cell in reading order).
        #[arg(long, value_parser = parse_cell)]
        start: Option<Cell>,
        /// Write the plan as JSON to this file.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write a picture of the plan to this file.
        #[arg(long)]
        svg: Option<PathBuf>,
    },
    /// Decode a captured lidar byte stream.
    LidarDecode {
        /// The capture file.
        file: PathBuf,
        /// Wire protocol.
        #[arg(long, default_value = "ld06")]
        protocol: String,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Drive a route with the real wheel controllers and odometry while the lidar maps.
    Drive {
        #[command(flatten)]
        map: MapArgs,
        /// A route file (`x y` metres per line), `square` (1 m, 10 laps), or
        /// `plan:PLANNER` (a complete coverage plan of the map).
        #[arg(long)]
        route: String,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[arg(long, value_enum, default_value = "none")]
        noise: NoiseArg,
        /// People walking about.
        #[arg(long, default_value_t = 0)]
        people: usize,
        /// Write a picture of the drive.
        #[arg(long)]
        svg: Option<PathBuf>,
        /// Write the measurements as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write the lidar's bytes to this file.
        #[arg(long)]
        capture: Option<PathBuf>,
        /// Flip a bit in this share of the lidar's bytes.
        #[arg(long, default_value_t = 0.0)]
        corrupt: f64,
    },
    /// Run a whole cleaning mission: the core's executive in closed loop with the physics.
    Mission {
        #[command(flatten)]
        map: MapArgs,
        /// known (a prior map is given) or unknown (mapped while cleaning).
        #[arg(long, value_enum, default_value = "known")]
        mode: ModeArg,
        /// People walking about.
        #[arg(long, default_value_t = 0)]
        people: usize,
        #[arg(long, value_enum, default_value = "none")]
        noise: NoiseArg,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Simulated time limit, seconds.
        #[arg(long, default_value_t = 7200.0)]
        max_time: f64,
        /// The dock X,Y in metres (default: a free spot near the centre).
        #[arg(long, value_parser = parse_point)]
        start: Option<(f64, f64)>,
        /// b-oha, ba, b-theta or b-oha-pc (ours).
        #[arg(long, default_value = "b-oha")]
        planner: String,
        /// Silence the lidar from A to B seconds (A,B) to exercise the fault.
        #[arg(long, value_parser = parse_point)]
        lidar_gap: Option<(f64, f64)>,
        /// Write the measurements as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write a picture of the mission.
        #[arg(long)]
        svg: Option<PathBuf>,
    },
    /// Benchmarks reproducing the papers' tables.
    Bench {
        #[command(subcommand)]
        which: BenchCmd,
    },
}

#[derive(Subcommand)]
enum BenchCmd {
    /// Seed 000 Table 1: A*, Theta*, OHA* on random 100x50 maps.
    Table1 {
        #[arg(long, default_value_t = 500)]
        runs: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Share of blocked cells, percent (default: the calibrated 20).
        #[arg(long, default_value_t = robovac::grid::maps::TABLE1_MAP.density_pct)]
        density: u32,
        /// Side of the corner squares starts and goals are drawn from.
        #[arg(long, default_value_t = robovac::grid::maps::TABLE1_CORNER)]
        corner: u32,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// The mission suite: studio, multi-room flat and office; known and unknown maps; 0, 1 and 3 people; both noise levels.
    Missions {
        /// Seeds per configuration (36 configurations).
        #[arg(long, default_value_t = 3)]
        runs: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Simulated time limit per mission, seconds.
        #[arg(long, default_value_t = 5400.0)]
        max_time: f64,
        /// Worker threads (default: the machine's cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Write every mission's results as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Wheel speed step response to 0.3 m/s (rise time, overshoot, steady-state error).
    WheelStep {
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Seed 000 Table 2: BA*, B-Theta*, B-OHA* and ours on random 50x30 and 30x50 maps.
    Table2 {
        #[arg(long, default_value_t = 500)]
        runs: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Share of blocked cells, percent.
        #[arg(long, default_value_t = robovac::grid::maps::TABLE2_MAP.density_pct)]
        density: u32,
        /// Largest obstacle side, cells.
        #[arg(long, default_value_t = robovac::grid::maps::TABLE2_MAP.max_side)]
        max_side: u32,
        /// Write the results as JSON to this file.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write an SVG of every planner's plan on the first maps here.
        #[arg(long)]
        svg_dir: Option<PathBuf>,
    },
}

fn parse_point(s: &str) -> Result<(f64, f64), String> {
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

fn parse_cell(s: &str) -> Result<Cell, String> {
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.cmd {
        Cmd::Demo => cmd_demo(),
        Cmd::Bench {
            which:
                BenchCmd::Missions {
                    runs,
                    seed,
                    max_time,
                    threads,
                    json,
                },
        } => cmd_bench_missions(runs, seed, max_time, threads, json.as_deref()),
        Cmd::Search {
            map,
            from,
            to,
            algo,
            json,
        } => cmd_search(&map, from, to, algo.into(), json),
        Cmd::Scen {
            scen,
            map,
            algo,
            json,
        } => cmd_scen(&scen, &map, algo.into(), json),
        Cmd::LidarDecode {
            file,
            protocol,
            json,
        } => cmd_lidar_decode(&file, &protocol, json),
        Cmd::Drive {
            map,
            route,
            seed,
            noise,
            people,
            svg,
            json,
            capture,
            corrupt,
        } => cmd_drive(
            &map,
            &route,
            seed,
            noise,
            people,
            svg.as_deref(),
            json.as_deref(),
            capture.as_deref(),
            corrupt,
        ),
        Cmd::Mission {
            map,
            mode,
            people,
            noise,
            seed,
            max_time,
            start,
            planner,
            lidar_gap,
            json,
            svg,
        } => {
            let kind = host_sim::plan::planner_by_name(&planner)
                .ok_or_else(|| format!("unknown planner {planner:?}"))?;
            if !(max_time.is_finite() && max_time > 0.0) {
                return Err("--max-time must be a positive number of seconds".into());
            }
            let (data, cell_m) = load_world_map(&map)?;
            let opts = host_sim::mission::MissionOptions {
                map: data,
                cell_m,
                mode: match mode {
                    ModeArg::Known => robovac::mission::MapMode::Known,
                    ModeArg::Unknown => robovac::mission::MapMode::Unknown,
                },
                people,
                noise: noise.into(),
                seed,
                max_time_s: max_time,
                start,
                kind,
                lidar_gap_s: lidar_gap,
            };
            cmd_mission(
                &opts,
                &map.map.display().to_string(),
                json.as_deref(),
                svg.as_deref(),
            )
        }
        Cmd::Bench {
            which: BenchCmd::WheelStep { seed },
        } => {
            for (name, n) in [
                ("none", host_sim::robot::Noise::None),
                ("realistic", host_sim::robot::Noise::Realistic),
            ] {
                let (rise, over, ss) = host_sim::drive::step_response(n, 0.3, seed);
                println!("wheel step 0 -> 0.3 m/s, noise {name:<9}: rise time (10-90 %) {:.0} ms, overshoot {:.1} %, steady-state error {:.2} %", rise * 1e3, over * 100.0, ss * 100.0);
            }
            Ok(())
        }
        Cmd::Plan {
            map,
            planner,
            start,
            json,
            svg,
        } => cmd_plan(&map, &planner, start, json.as_deref(), svg.as_deref()),
        Cmd::Bench {
            which:
                BenchCmd::Table2 {
                    runs,
                    seed,
                    density,
                    max_side,
                    json,
                    svg_dir,
                },
        } => cmd_table2(
            runs,
            seed,
            density,
            max_side,
            json.as_deref(),
            svg_dir.as_deref(),
        ),
        Cmd::Bench {
            which:
                BenchCmd::Table1 {
                    runs,
                    seed,
                    density,
                    corner,
                    json,
                },
        } => cmd_table1(runs, seed, density, corner, json),
    }
}

fn cmd_search(args: &MapArgs, from: Cell, to: Cell, algo: Algo, json: bool) -> Result<(), String> {
    let map = args.load()?;
    let mut grid = new_grid();
    map.to_grid(&mut *grid).map_err(|e| e.to_string())?;
    let mut state = new_search();
    let mut path = vec![Cell::default(); grid.cells()];
    let t0 = Instant::now();
    let stats = state
        .search(&*grid, from, &[to], algo)
        .map_err(|e| format!("{}: {e}", args.map.display()))?;
    let n = state.write_path(&mut path).map_err(|e| e.to_string())?;
    let us = t0.elapsed().as_secs_f64() * 1e6;
    let full = path[..n].to_vec();
    let m = prune(&*grid, &mut path[..n]);
    let pruned = &path[..m];
    let cost = polyline_length(&full);
    let pruned_len = polyline_length(pruned);
    if json {
        let pts = |p: &[Cell]| p.iter().map(|c| json!([c.x, c.y])).collect::<Vec<_>>();
        let out = json!({
            "map": args.map.display().to_string(),
            "algo": algo_name(algo),
            "from": [from.x, from.y],
            "to": [to.x, to.y],
            "path": pts(&full),
            "cost": cost,
            "pruned_path": pts(pruned),
            "pruned_length": pruned_len,
            "nodes_expanded": stats.nodes_expanded,
            "time_us": us,
        });
        println!("{out}");
    } else {
        let fmt = |p: &[Cell]| {
            p.iter()
                .map(|c| format!("({},{})", c.x, c.y))
                .collect::<Vec<_>>()
                .join(" ")
        };
        println!("algo            {}", algo_name(algo));
        println!("path            {}", fmt(&full));
        println!("cost            {cost:.4} cells ({} cells on the path)", n);
        println!("pruned          {}", fmt(pruned));
        println!("pruned length   {pruned_len:.4} cells ({m} waypoints)");
        println!("nodes expanded  {}", stats.nodes_expanded);
        println!("time            {us:.1} us");
    }
    Ok(())
}

fn cmd_scen(scen: &Path, args: &MapArgs, algo: Algo, json: bool) -> Result<(), String> {
    let bytes = std::fs::read(scen).map_err(|e| format!("{}: cannot read: {e}", scen.display()))?;
    let problems = parse_scen(scen, &bytes).map_err(|e| e.to_string())?;
    let map = args.load()?;
    let rep = run_scen(&map, &problems, algo).map_err(|e| e.to_string())?;
    if json {
        let out = json!({
            "algo": rep.algo,
            "problems": rep.problems,
            "solved": rep.solved,
            "optimal_mismatches": rep.optimal_mismatches,
            "mean_cost_ratio": rep.mean_cost_ratio,
            "mean_nodes_expanded": rep.mean_nodes_expanded,
            "median_query_us": rep.median_query_us,
            "mean_pruned_cost": rep.mean_pruned_cost,
            "mismatch_examples": rep.mismatch_examples,
        });
        println!("{out}");
    } else {
        println!("scenario             {}", scen.display());
        println!("algo                 {}", rep.algo);
        println!("problems             {}", rep.problems);
        println!("solved               {}", rep.solved);
        println!("optimal mismatches   {}", rep.optimal_mismatches);
        println!("mean cost ratio      {:.6}", rep.mean_cost_ratio);
        println!("mean nodes expanded  {:.1}", rep.mean_nodes_expanded);
        println!("median query         {:.1} us", rep.median_query_us);
        for m in &rep.mismatch_examples {
            println!("  mismatch: {m}");
        }
    }
    Ok(())
}

fn cmd_table1(runs: usize, seed: u64, density: u32, corner: u32, json: bool) -> Result<(), String> {
    if runs == 0 {
        return Err("--runs must be at least 1".into());
    }
    if density > 60 {
        return Err("--density above 60 % leaves almost no reachable pairs".into());
    }
    let map = robovac::grid::maps::RandomMap {
        density_pct: density,
        ..robovac::grid::maps::TABLE1_MAP
    };
    let rows = host_sim::bench::table1(runs, seed, map, corner, |done, total| {
        if !json && std::io::stderr().is_terminal() && (done % 10 == 0 || done == total) {
            let w = 40 * done / total;
            eprint!("\r[{}{}] {done}/{total}", "#".repeat(w), " ".repeat(40 - w));
            let _ = std::io::stderr().flush();
            if done == total {
                eprintln!();
            }
        }
    });
    if json {
        let mut obj = serde_json::Map::new();
        obj.insert("runs".into(), json!(runs));
        obj.insert("seed".into(), json!(seed));
        obj.insert("density_pct".into(), json!(density));
        obj.insert("corner".into(), json!(corner));
        for r in &rows {
            obj.insert(
                r.algo.into(),
                json!({
                    "mean_time_us": r.mean_time_us,
                    "mean_cost": r.mean_cost,
                    "mean_cost_unpruned": r.mean_cost_unpruned,
                    "mean_cost_pruned": r.mean_cost_pruned,
                    "mean_nodes": r.mean_nodes,
                    "paper": {"time_s": r.paper.0, "cost": r.paper.1, "nodes": r.paper.2},
                }),
            );
        }
        println!("{}", serde_json::Value::Object(obj));
    } else {
        println!("Seed 000 Table 1: {runs} random 100x50 maps ({density}% blocked, corner {corner}), seed {seed}");
        println!(
            "{:<7} {:>12} {:>10} | {:>10} {:>10} {:>10} | {:>10} {:>10}",
            "algo", "ours us", "paper s", "ours cost", "pruned", "paper", "ours nodes", "paper"
        );
        for r in &rows {
            println!(
                "{:<7} {:>12.1} {:>10.2} | {:>10.2} {:>10.2} {:>10.2} | {:>10.1} {:>10.2}",
                r.algo,
                r.mean_time_us,
                r.paper.0,
                r.mean_cost,
                r.mean_cost_pruned,
                r.paper.1,
                r.mean_nodes,
                r.paper.2
            );
        }
        println!("cost = A* unpruned 8-connected, Theta* any-angle, OHA* after pruning (as in the paper)");
        if let (Some(a), Some(o)) = (
            rows.iter().find(|r| r.algo == "astar"),
            rows.iter().find(|r| r.algo == "oha"),
        ) {
            println!(
                "OHA*/A* nodes {:.3} (paper {:.3}); OHA* pruned cost / A* cost {:.4} (paper {:.4})",
                o.mean_nodes / a.mean_nodes,
                659.45 / 1267.55,
                o.mean_cost / a.mean_cost,
                115.78 / 120.94
            );
        }
    }
    Ok(())
}

fn write_file(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

fn cmd_plan(
    args: &MapArgs,
    planner: &str,
    start: Option<Cell>,
    json: Option<&Path>,
    svg: Option<&Path>,
) -> Result<(), String> {
    let kind = host_sim::plan::planner_by_name(planner)
        .ok_or_else(|| format!("unknown planner {planner:?} (b-oha, ba, b-theta, b-oha-pc)"))?;
    let map = args.load()?;
    let p = host_sim::plan::plan(&map, kind, start)
        .map_err(|e| format!("{}: {e}", args.map.display()))?;
    let m = host_sim::plan::metrics_json(&p);
    println!(
        "planner {} on {} ({}x{} cells)",
        kind.name(),
        args.map.display(),
        map.width,
        map.height
    );
    if let Some(obj) = m.as_object() {
        for (k, v) in obj {
            println!("  {k:<24} {v}");
        }
    }
    if let Some(f) = json {
        write_file(f, &host_sim::plan::plan_json(&map, &p).to_string())?;
    }
    if let Some(f) = svg {
        write_file(
            f,
            &host_sim::svg::plan_svg(&map, &p, &args.map.display().to_string()),
        )?;
    }
    Ok(())
}

fn cmd_table2(
    runs: usize,
    seed: u64,
    density: u32,
    max_side: u32,
    json: Option<&Path>,
    svg_dir: Option<&Path>,
) -> Result<(), String> {
    use host_sim::bench::paper_table2;
    if runs == 0 {
        return Err("--runs must be at least 1".into());
    }
    if density > 60 || max_side == 0 {
        return Err("--density must be at most 60 and --max-side at least 1".into());
    }
    if let Some(d) = svg_dir {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let spec = robovac::grid::maps::RandomMap {
        density_pct: density,
        max_side,
        ..robovac::grid::maps::TABLE2_MAP
    };
    let mut svg_err = None;
    let tty = std::io::stderr().is_terminal();
    let rows = host_sim::bench::table2(
        runs,
        seed,
        spec,
        |label, run, map, p| {
            if let Some(d) = svg_dir {
                if run < 3 {
                    let f = d.join(format!("table2_{label}_{run}_{}.svg", p.kind.name()));
                    if let Err(e) = write_file(
                        &f,
                        &host_sim::svg::plan_svg(map, p, &format!("Table 2 {label} map {run}")),
                    ) {
                        svg_err = Some(e);
                    }
                }
            }
        },
        |done, total| {
            if done % 10 == 0 || done == total {
                let w = 40 * done / total;
                if tty {
                    eprint!(
                        "\r[{}{}] {done}/{total} maps",
                        "#".repeat(w),
                        " ".repeat(40 - w)
                    );
                    if done == total {
                        eprintln!();
                    }
                } else if done % (total / 4).max(1) == 0 || done == total {
                    eprintln!(
                        "[{}{}] {done}/{total} maps",
                        "#".repeat(w),
                        " ".repeat(40 - w)
                    );
                }
                let _ = std::io::stderr().flush();
            }
        },
    )?;
    if let Some(e) = svg_err {
        return Err(e);
    }
    println!("Seed 000 Table 2: {runs} random maps per size ({density}% blocked, rectangles up to {max_side} cells), seed {seed}");
    let metrics = [
        "coverage_path_length",
        "segments",
        "turns",
        "backtrack_path_length",
        "backtrack_points_total",
        "time_us",
        "coverage",
        "repetition",
        "total_path_length",
        "rotation_deg",
        "nodes_expanded",
        "backtrack_points_kept",
    ];
    for (label, _, _) in host_sim::bench::TABLE2_SIZES {
        let wide = label == "30x50";
        println!(
            "\n{label} ({})",
            if wide {
                "wide: 30 rows x 50 columns"
            } else {
                "tall: 50 rows x 30 columns"
            }
        );
        print!("{:<24}", "metric");
        for (l, k, _) in rows.iter().filter(|r| r.0 == label) {
            let _ = l;
            print!(" {:>10} {:>9}", k.name(), "paper");
        }
        println!();
        for m in metrics {
            print!("{m:<24}");
            for (_, k, agg) in rows.iter().filter(|r| r.0 == label) {
                let ours = agg.mean(m);
                let paper = if m == "time_us" {
                    paper_table2("time_s", *k, wide).map(|s| s * 1e6)
                } else {
                    paper_table2(m, *k, wide)
                };
                match paper {
                    Some(pv) => print!(" {ours:>10.2} {pv:>9.2}"),
                    None => print!(" {ours:>10.2} {:>9}", "-"),
                }
            }
            println!();
        }
        print!("{:<24}", "min coverage");
        for (_, _, agg) in rows.iter().filter(|r| r.0 == label) {
            print!(" {:>10.4} {:>9}", agg.min_coverage, "");
        }
        println!();
    }
    // The paper's claims, as measured ratios against our BA*.
    println!("\nratios against our BA* on the same maps (paper in brackets):");
    for (label, _, _) in host_sim::bench::TABLE2_SIZES {
        let get = |k: robovac::coverage::PlannerKind, m: &str| {
            rows.iter()
                .find(|r| r.0 == label && r.1 == k)
                .map(|r| r.2.mean(m))
                .unwrap_or(0.0)
        };
        use robovac::coverage::PlannerKind::*;
        for (m, paper) in [
            ("segments", "-19%"),
            ("backtrack_points_total", "-81%"),
            ("backtrack_points_kept", "-81%"),
            ("backtrack_path_length", "-10%"),
            ("turns", if label == "30x50" { "-15%" } else { "" }),
        ] {
            let ba = get(BaStar, m);
            let rel = |k| {
                if ba > 0.0 {
                    100.0 * (get(k, m) / ba - 1.0)
                } else {
                    0.0
                }
            };
            println!(
                "  {label} {m:<24} B-OHA* {:+6.1}% [{paper:>4}]   B-Theta* {:+6.1}%   ours {:+6.1}%",
                rel(BOha),
                rel(BTheta),
                rel(BOhaPc)
            );
        }
        let bo = get(BOha, "backtrack_path_length");
        let ours = get(BOhaPc, "backtrack_path_length");
        println!(
            "  {label} ours vs B-OHA*: backtracking path x{:.3}, turns x{:.3}",
            if bo > 0.0 { ours / bo } else { 0.0 },
            get(BOhaPc, "turns") / get(BOha, "turns").max(1e-9)
        );
    }
    if let Some(f) = json {
        let mut obj = serde_json::Map::new();
        obj.insert("runs".into(), json!(runs));
        obj.insert("seed".into(), json!(seed));
        obj.insert("density_pct".into(), json!(density));
        obj.insert("max_side".into(), json!(max_side));
        for (label, k, agg) in &rows {
            let mut means = serde_json::Map::new();
            for (m, _) in agg.sums.iter() {
                means.insert((*m).to_string(), json!(agg.mean(m)));
            }
            let mut t = agg.times_us.clone();
            means.insert(
                "median_time_us".into(),
                json!(host_sim::metrics::median(&mut t)),
            );
            means.insert("min_coverage".into(), json!(agg.min_coverage));
            let entry = obj.entry(label.to_string()).or_insert_with(|| json!({}));
            if let Some(e) = entry.as_object_mut() {
                e.insert(k.name().into(), serde_json::Value::Object(means));
            }
        }
        write_file(f, &serde_json::Value::Object(obj).to_string())?;
    }
    Ok(())
}

fn cmd_lidar_decode(file: &Path, protocol: &str, json: bool) -> Result<(), String> {
    use robovac::robot::lidar::LidarProtocol;
    if protocol != "ld06" {
        return Err(format!("unknown protocol {protocol:?} (supported: ld06)"));
    }
    let bytes = std::fs::read(file).map_err(|e| format!("{}: cannot read: {e}", file.display()))?;
    let mut p = robovac::robot::lidar::ld06::Ld06::new();
    let (mut points, mut valid, mut speed_sum) = (0u64, 0u64, 0u64);
    for &b in &bytes {
        if let Some(f) = p.feed(b) {
            points += f.count as u64;
            valid += f.points().iter().filter(|q| q.dist_mm > 0).count() as u64;
            speed_sum += f.speed_dps as u64;
        }
    }
    let s = p.stats();
    let mean_speed = if s.frames > 0 {
        speed_sum as f64 / s.frames as f64
    } else {
        0.0
    };
    if json {
        println!(
            "{}",
            json!({
                "protocol": protocol, "bytes": s.bytes, "frames": s.frames, "crc_failures": s.crc_failures,
                "rejected": s.rejected, "rejected_speed": s.rejected_speed, "rejected_span": s.rejected_span,
                "rejected_timestamp": s.rejected_timestamp, "bytes_skipped": s.bytes_skipped,
                "points": points, "points_with_return": valid, "mean_speed_dps": mean_speed,
            })
        );
    } else {
        println!("{}: {} bytes, {} frames, {} CRC failures, {} rejected, {} skipped bytes, {} points ({} with a return), mean speed {:.1} deg/s",
            file.display(), s.bytes, s.frames, s.crc_failures, s.rejected, s.bytes_skipped, points, valid, mean_speed);
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn cmd_drive(
    args: &MapArgs,
    route: &str,
    seed: u64,
    noise: NoiseArg,
    people: usize,
    svg: Option<&Path>,
    json: Option<&Path>,
    capture: Option<&Path>,
    corrupt: f64,
) -> Result<(), String> {
    use host_sim::drive::{drive, drive_svg, parse_route, DriveOptions, Route};
    let (map, cell_m) = load_world_map(args)?;
    let route = if route == "square" {
        Route::Square {
            side_m: 1.0,
            laps: 10,
        }
    } else if let Some(name) = route.strip_prefix("plan:") {
        Route::Plan(
            host_sim::plan::planner_by_name(name)
                .ok_or_else(|| format!("unknown planner {name:?} in --route plan:NAME"))?,
        )
    } else {
        let text =
            std::fs::read_to_string(route).map_err(|e| format!("{route}: cannot read: {e}"))?;
        Route::Points(parse_route(&text).map_err(|e| format!("{route}: {e}"))?)
    };
    if !(0.0..=1.0).contains(&corrupt) {
        return Err("--corrupt must be a share between 0 and 1".into());
    }
    let noise = match noise {
        NoiseArg::None => host_sim::robot::Noise::None,
        NoiseArg::Realistic => host_sim::robot::Noise::Realistic,
    };
    let t0 = Instant::now();
    let (rep, trace) = drive(DriveOptions {
        map: map.clone(),
        cell_m,
        route,
        noise,
        seed,
        people,
        capture: capture.is_some(),
        corrupt,
        evidence_mm: 50,
    })
    .map_err(|e| format!("{}: {e}", args.map.display()))?;
    let wall = t0.elapsed().as_secs_f64();
    let out = json!({
        "completed": rep.completed,
        "sim_time_s": rep.sim_time_s,
        "wall_time_s": wall,
        "distance_m": rep.distance_m,
        "odometry": {
            "final_position_error_mm": rep.final_position_error_mm,
            "final_heading_error_mrad": rep.final_heading_error_mrad,
            "max_position_error_mm": rep.max_position_error_mm,
        },
        "collisions": rep.collisions,
        "floor_coverage": rep.floor_coverage,
        "waypoints": rep.waypoints,
        "lidar": {"frames": rep.parser.frames, "crc_failures": rep.parser.crc_failures, "rejected": rep.parser.rejected, "scans": rep.scans},
        "map": {
            "cells_seen": rep.map_cells_seen,
            "correct_share": rep.map_correct_share,
            "false_obstacle_share": rep.map_false_obstacle_share,
            "false_free_share": rep.map_false_free_share,
            "path_false_obstacle_rate": rep.path_false_obstacle_rate,
        },
    });
    println!(
        "drive on {}: {:.1} m in {:.1} s simulated ({:.1} s wall), route completed: {}",
        args.map.display(),
        rep.distance_m,
        rep.sim_time_s,
        wall,
        rep.completed
    );
    println!(
        "  odometry error at the end: {:.1} mm, {:.2} mrad (max during the run {:.1} mm)",
        rep.final_position_error_mm, rep.final_heading_error_mrad, rep.max_position_error_mm
    );
    println!(
        "  floor swept: {:.2} % of the reachable floor ({} waypoints)",
        100.0 * rep.floor_coverage,
        rep.waypoints
    );
    println!(
        "  collisions: {}; lidar frames {} (CRC failures {}, rejected {}), scans {}",
        rep.collisions, rep.parser.frames, rep.parser.crc_failures, rep.parser.rejected, rep.scans
    );
    println!("  map: {} cells seen, {:.2} % classified correctly, false obstacles: {:.2} % of free cells seen, {:.3} % along the path",
        rep.map_cells_seen, 100.0 * rep.map_correct_share, 100.0 * rep.map_false_obstacle_share, 100.0 * rep.path_false_obstacle_rate);
    if let Some(f) = json {
        write_file(f, &out.to_string())?;
    }
    if let Some(f) = svg {
        write_file(
            f,
            &drive_svg(
                &map,
                cell_m,
                &trace,
                &rep,
                &format!("drive on {}", args.map.display()),
            ),
        )?;
    }
    if let (Some(f), Some(bytes)) = (capture, trace.capture.as_ref()) {
        std::fs::write(f, bytes).map_err(|e| format!("{}: cannot write: {e}", f.display()))?;
    }
    Ok(())
}

impl From<NoiseArg> for host_sim::robot::Noise {
    fn from(n: NoiseArg) -> Self {
        match n {
            NoiseArg::None => host_sim::robot::Noise::None,
            NoiseArg::Realistic => host_sim::robot::Noise::Realistic,
        }
    }
}

/// A floor for the simulated world: images keep their own resolution (PNG,
/// PGM, ROS YAML); ASCII and MovingAI maps take --cell (default 0.1 m).
fn load_world_map(args: &MapArgs) -> Result<(MapData, f64), String> {
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

/// Runs one mission with a progress line on a terminal.
fn cmd_mission(
    opts: &host_sim::mission::MissionOptions,
    name: &str,
    json: Option<&Path>,
    svg: Option<&Path>,
) -> Result<(), String> {
    use host_sim::mission::{mission_svg, report_json, run_mission, summary};
    let tty = std::io::stderr().is_terminal();
    let (rep, trace, floor) = run_mission(opts, |t, state, cov| {
        if tty {
            eprint!(
                "\r  {t:>6.0} s simulated · {state:?} · {:.1} % swept      ",
                100.0 * cov
            );
        }
    })
    .map_err(|e| format!("{name}: {e}"))?;
    if tty {
        eprintln!();
    }
    println!(
        "mission on {name} ({:?} map, {} people, seed {}):",
        opts.mode, opts.people, opts.seed
    );
    println!("  {}", summary(&rep));
    if let Some(f) = json {
        write_file(f, &report_json(&rep).to_string())?;
    }
    if let Some(f) = svg {
        let title = format!(
            "mission on {name}: {:?} map, {} people, noise {:?}, seed {}",
            opts.mode, opts.people, opts.noise, opts.seed
        );
        write_file(
            f,
            &mission_svg(&opts.map, opts.cell_m, &floor, &trace, &rep, &title),
        )?;
    }
    Ok(())
}

/// `host-sim demo`: the product at work.
fn cmd_demo() -> Result<(), String> {
    use host_sim::mission::{mission_svg, run_mission, suite_map, summary, MissionOptions};
    let map = suite_map("home")?;
    let opts = MissionOptions {
        map,
        cell_m: 0.1,
        mode: robovac::mission::MapMode::Known,
        people: 2,
        noise: host_sim::robot::Noise::None,
        seed: 1,
        max_time_s: 5400.0,
        start: None,
        kind: robovac::coverage::PlannerKind::BOha,
        lidar_gap_s: None,
    };
    println!(
        "robovac demo: the firmware's mission executive cleans a 9.6 m × 7.2 m furnished flat"
    );
    println!(
        "(living room, kitchen, hallway, two bedrooms, bathroom) while two people walk about."
    );
    let tty = std::io::stdout().is_terminal();
    let (rep, trace, floor) = run_mission(&opts, |t, state, cov| {
        if tty {
            print!(
                "\r  {t:>6.0} s simulated · {state:?} · {:.1} % of the floor swept      ",
                100.0 * cov
            );
        } else if (t as u64).is_multiple_of(300) {
            println!(
                "  {t:>6.0} s simulated · {state:?} · {:.1} % of the floor swept",
                100.0 * cov
            );
        }
        let _ = std::io::stdout().flush();
    })?;
    if tty {
        println!();
    }
    println!("  {}", summary(&rep));
    let svg = mission_svg(
        &opts.map,
        opts.cell_m,
        &floor,
        &trace,
        &rep,
        "robovac demo: known map, two people walking, ideal sensors",
    );
    write_file(Path::new("demo.svg"), &svg)?;
    println!(
        "  picture: demo.svg (swept floor green, missed red, the robot's path blue, people orange)"
    );
    Ok(())
}

/// `host-sim bench missions`.
fn cmd_bench_missions(
    runs: usize,
    seed: u64,
    max_time: f64,
    threads: Option<usize>,
    json: Option<&Path>,
) -> Result<(), String> {
    use host_sim::mission::{report_json, run_suite, suite_cases};
    if runs == 0 {
        return Err("--runs must be at least 1".into());
    }
    if !(max_time.is_finite() && max_time > 0.0) {
        return Err("--max-time must be a positive number of seconds".into());
    }
    let cases = suite_cases(runs, seed);
    let threads = threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let tty = std::io::stderr().is_terminal();
    let t0 = Instant::now();
    let results = run_suite(&cases, max_time, threads, |done, total| {
        let w = 40 * done / total;
        let line = format!(
            "[{}{}] {done}/{total} missions, {:.0} s",
            "#".repeat(w),
            " ".repeat(40 - w),
            t0.elapsed().as_secs_f64()
        );
        if tty {
            eprint!("\r{line}");
            if done == total {
                eprintln!();
            }
        } else if done % (total / 10).max(1) == 0 || done == total {
            eprintln!("{line}");
        }
        let _ = std::io::stderr().flush();
    });
    let wall = t0.elapsed().as_secs_f64();
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for (c, r) in cases.iter().zip(&results) {
        match r {
            Ok(rep) => rows.push((c, rep)),
            Err(e) => failures.push(format!(
                "{} {:?} {} people seed {}: {e}",
                c.map, c.mode, c.people, c.seed
            )),
        }
    }
    println!(
        "Mission suite: {} missions ({} seeds per configuration), {:.0} s wall on {threads} threads",
        cases.len(),
        runs,
        wall
    );
    println!(
        "{:<7} {:<8} {:<10} {:>3} {:>8} {:>8} {:>9} {:>9} {:>6} {:>5} {:>6} {:>6} {:>7} {:>7}",
        "map",
        "mode",
        "noise",
        "n",
        "finished",
        "returned",
        "cover avg",
        "cover min",
        "repet",
        "coll",
        "people",
        "avoid",
        "t/ideal",
        "sim×"
    );
    let mut groups: Vec<(String, String, String)> = Vec::new();
    for (c, _) in &rows {
        let k = (
            c.map.to_string(),
            format!("{:?}", c.mode).to_lowercase(),
            format!("{:?}", c.noise).to_lowercase(),
        );
        if !groups.contains(&k) {
            groups.push(k);
        }
    }
    for g in &groups {
        let sel: Vec<&host_sim::mission::MissionReport> = rows
            .iter()
            .filter(|(c, _)| {
                c.map == g.0
                    && format!("{:?}", c.mode).to_lowercase() == g.1
                    && format!("{:?}", c.noise).to_lowercase() == g.2
            })
            .map(|(_, r)| *r)
            .collect();
        let n = sel.len() as f64;
        let mean = |f: &dyn Fn(&host_sim::mission::MissionReport) -> f64| {
            sel.iter().map(|r| f(r)).sum::<f64>() / n
        };
        println!(
            "{:<7} {:<8} {:<10} {:>3} {:>8} {:>8} {:>8.2}% {:>8.2}% {:>6.2} {:>5} {:>6} {:>6.1} {:>7.2} {:>7.0}",
            g.0,
            g.1,
            g.2,
            sel.len(),
            sel.iter().filter(|r| r.finished).count(),
            sel.iter().filter(|r| r.returned_to_start).count(),
            100.0 * mean(&|r| r.coverage),
            100.0 * sel.iter().map(|r| r.coverage).fold(1.0, f64::min),
            mean(&|r| r.repetition),
            sel.iter().map(|r| r.collisions).sum::<usize>(),
            sel.iter().map(|r| r.person_contacts).sum::<usize>(),
            mean(&|r| r.avoidance_events as f64),
            mean(&|r| r.sim_time_s / r.ideal_time_s.max(1e-9)),
            mean(&|r| r.sim_time_s / r.wall_time_s.max(1e-9)),
        );
    }
    let total_coll: usize = rows.iter().map(|(_, r)| r.collisions).sum();
    println!(
        "collisions (the robot moving into something): {total_coll} over {} missions",
        rows.len()
    );
    for (mode, label) in [
        (robovac::mission::MapMode::Known, "known"),
        (robovac::mission::MapMode::Unknown, "unknown"),
    ] {
        let sel: Vec<_> = rows
            .iter()
            .filter(|(c, _)| c.mode == mode && c.noise == host_sim::robot::Noise::None)
            .collect();
        if sel.is_empty() {
            continue;
        }
        println!(
            "noise none, {label} map: coverage min {:.2} %, mean {:.2} %; finished {}/{}; back at the start {}/{}",
            100.0 * sel.iter().map(|(_, r)| r.coverage).fold(1.0, f64::min),
            100.0 * sel.iter().map(|(_, r)| r.coverage).sum::<f64>() / sel.len() as f64,
            sel.iter().filter(|(_, r)| r.finished).count(),
            sel.len(),
            sel.iter().filter(|(_, r)| r.returned_to_start).count(),
            sel.len()
        );
    }
    let sim: f64 = rows.iter().map(|(_, r)| r.sim_time_s).sum();
    let wall_sum: f64 = rows.iter().map(|(_, r)| r.wall_time_s).sum();
    println!("simulator speed: {:.0} simulated seconds per wall second per thread ({:.0} s simulated in all)", sim / wall_sum.max(1e-9), sim);
    for f in &failures {
        println!("error: {f}");
    }
    if let Some(f) = json {
        let arr: Vec<serde_json::Value> = rows
            .iter()
            .map(|(c, r)| {
                let mut v = report_json(r);
                v["map"] = json!(c.map);
                v["mode"] = json!(format!("{:?}", c.mode).to_lowercase());
                v["people"] = json!(c.people);
                v["noise"] = json!(format!("{:?}", c.noise).to_lowercase());
                v["seed"] = json!(c.seed);
                v
            })
            .collect();
        write_file(f, &serde_json::Value::Array(arr).to_string())?;
    }
    if !failures.is_empty() {
        return Err(format!("{} missions could not run", failures.len()));
    }
    Ok(())
}
