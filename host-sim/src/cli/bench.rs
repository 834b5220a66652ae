//! `host-sim bench`: the papers' tables, the mission suite and the wheel
//! step response.

use std::path::{Path, PathBuf};

use super::args::{write_file, NoiseArg};
use super::progress;
use host_sim::run::bench::paper_table2;
use serde_json::json;

/// Which benchmark.
#[derive(clap::Subcommand)]
pub enum BenchCmd {
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
        /// Limit on each mission's simulated cleaning time (charging does
        /// not count), seconds.
        #[arg(long, default_value_t = 10800.0)]
        max_time: f64,
        /// Worker threads (default: the machine's cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Write every mission's results as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Maps: the flats (studio, home, office) and the real homes (S8,
        /// z10, 1c, S6, 3790, l10su); `flats` or `homes` for each set.
        #[arg(long, value_delimiter = ',', default_value = "flats")]
        maps: Vec<String>,
        /// People walking about (a list).
        #[arg(long, value_delimiter = ',', default_value = "0,1,3")]
        people: Vec<usize>,
        /// Noise levels (a list of none, realistic, harsh).
        #[arg(
            long,
            value_enum,
            value_delimiter = ',',
            default_value = "none,realistic"
        )]
        noise: Vec<NoiseArg>,
        /// Leave out the real homes' own no-go zones and virtual walls
        /// (the whole home cleaned, as issue 10's figures were measured).
        #[arg(long)]
        no_map_zones: bool,
        /// The local planner that steers the avoidances: dwa, or apf (the
        /// potential field; its local minima are counted).
        #[arg(long, value_enum, default_value = "dwa")]
        local: super::args::LocalArg,
    },
    /// Our A* against the `pathfinding` crate's, on the same MovingAI queries in one run (medians and their ratio).
    Peers {
        /// The .scen file.
        #[arg(long)]
        scen: PathBuf,
        #[command(flatten)]
        map: super::args::MapArgs,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// D* Lite against A* from nothing, as obstacles appear ahead of a robot walking MovingAI problems, or its ways home on a real home (nodes and time per replan).
    Replan {
        /// The .scen file.
        #[arg(long, required_unless_present = "to_dock", conflicts_with = "to_dock")]
        scen: Option<PathBuf>,
        /// Instead of a scenario: ways home to the map's charger (a
        /// ValetudoMap), on its configuration space for the robot.
        #[arg(long)]
        to_dock: bool,
        #[command(flatten)]
        map: super::args::MapArgs,
        /// How many problems, the scenario's last (longest).
        #[arg(long, default_value_t = 50)]
        problems: usize,
        /// Cells walked between two obstacles.
        #[arg(long, default_value_t = 10)]
        every: usize,
        /// How far along the path an obstacle appears, cells.
        #[arg(long, default_value_t = 4)]
        ahead: usize,
        /// Obstacles per problem at most.
        #[arg(long, default_value_t = 20)]
        changes: usize,
        /// An obstacle's side, cells (odd).
        #[arg(long, default_value_t = 3)]
        side: usize,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Every coverage planner on every map, each plan checked cell by cell (tables per map, a summary, the best per metric marked).
    Coverage {
        /// Map files and directories (their .map, .json, .png, .pgm, .yaml and .txt files).
        #[arg(long, value_delimiter = ',', required = true)]
        maps: Vec<PathBuf>,
        /// Planners (names, or all).
        #[arg(long, value_delimiter = ',', default_value = "all")]
        planners: Vec<String>,
        /// Cell side for image and Valetudo maps, metres (grid maps are planned cell for cell).
        #[arg(long, default_value_t = 0.3)]
        cell: f64,
        /// Write every plan's metrics as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write one picture per map and planner into this directory.
        #[arg(long)]
        svg_dir: Option<PathBuf>,
    },
    /// The seeds' own experiments (seeds 001, 002, 003) beside the numbers they report.
    Seeds {
        /// Write the figures as JSON.
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

/// Runs the benchmark.
pub fn run(which: BenchCmd) -> Result<(), String> {
    match which {
        BenchCmd::Table1 {
            runs,
            seed,
            density,
            corner,
            json,
        } => cmd_table1(runs, seed, density, corner, json),
        BenchCmd::Table2 {
            runs,
            seed,
            density,
            max_side,
            json,
            svg_dir,
        } => cmd_table2(
            runs,
            seed,
            density,
            max_side,
            json.as_deref(),
            svg_dir.as_deref(),
        ),
        BenchCmd::Missions {
            runs,
            seed,
            max_time,
            threads,
            json,
            maps,
            people,
            noise,
            no_map_zones,
            local,
        } => {
            let noises: Vec<_> = noise.into_iter().map(Into::into).collect();
            let maps = super::bench_missions::suite_map_names(&maps)?;
            let sel = super::bench_missions::SuiteSelection {
                maps: &maps,
                people: &people,
                noises: &noises,
                map_zones: !no_map_zones,
                local: local.into(),
            };
            super::bench_missions::run(runs, seed, max_time, threads, json.as_deref(), &sel)
        }
        BenchCmd::Peers { scen, map, json } => super::bench_peers::run(&scen, &map, json),
        BenchCmd::Replan {
            scen,
            to_dock: _,
            map,
            problems,
            every,
            ahead,
            changes,
            side,
            json,
        } => {
            let how = host_sim::run::replan::Changes {
                every,
                ahead,
                changes,
                side,
            };
            super::bench_replan::run(scen.as_deref(), &map, problems, how, json)
        }
        BenchCmd::Coverage {
            maps,
            planners,
            cell,
            json,
            svg_dir,
        } => super::bench_coverage::run(super::bench_coverage::Opts {
            maps,
            planners,
            cell_m: cell,
            json,
            svg_dir,
        }),
        BenchCmd::Seeds { json } => super::bench_seeds::run(json),
        BenchCmd::WheelStep { seed } => cmd_wheel_step(seed),
    }
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
    let pb = progress::bar(runs, "maps");
    let rows = host_sim::run::bench::table1(runs, seed, map, corner, |done, _| {
        pb.set_position(done as u64);
    });
    pb.finish_and_clear();
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

fn cmd_table2(
    runs: usize,
    seed: u64,
    density: u32,
    max_side: u32,
    json: Option<&Path>,
    svg_dir: Option<&Path>,
) -> Result<(), String> {
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
    let pb = progress::bar(2 * runs, "maps");
    let rows = host_sim::run::bench::table2(
        runs,
        seed,
        spec,
        |label, run, map, p| {
            if let Some(d) = svg_dir {
                if run < 3 {
                    let f = d.join(format!("table2_{label}_{run}_{}.svg", p.kind.name()));
                    if let Err(e) = write_file(
                        &f,
                        &host_sim::report::svg::plan_svg(
                            map,
                            p,
                            &format!("Table 2 {label} map {run}"),
                        ),
                    ) {
                        svg_err = Some(e);
                    }
                }
            }
        },
        |done, total| {
            pb.set_length(total as u64);
            pb.set_position(done as u64);
        },
    )?;
    pb.finish_and_clear();
    if let Some(e) = svg_err {
        return Err(e);
    }
    println!("Seed 000 Table 2: {runs} random maps per size ({density}% blocked, rectangles up to {max_side} cells), seed {seed}");
    print_table2_means(&rows);
    print_table2_ratios(&rows);
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
                json!(host_sim::report::metrics::median(&mut t)),
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

/// Table 2's means per size and planner, beside the paper's.
fn print_table2_means(
    rows: &[(
        &str,
        robovac::coverage::PlannerKind,
        host_sim::run::bench::Table2Agg,
    )],
) {
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
    for (label, _, _) in host_sim::run::bench::TABLE2_SIZES {
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
}

/// The paper's claims, as measured ratios against our BA*.
fn print_table2_ratios(
    rows: &[(
        &str,
        robovac::coverage::PlannerKind,
        host_sim::run::bench::Table2Agg,
    )],
) {
    println!("\nratios against our BA* on the same maps (paper in brackets):");
    for (label, _, _) in host_sim::run::bench::TABLE2_SIZES {
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
}

/// `bench wheel-step`.
fn cmd_wheel_step(seed: u64) -> Result<(), String> {
    for (name, n) in [
        ("none", host_sim::sim::robot::Noise::None),
        ("realistic", host_sim::sim::robot::Noise::Realistic),
    ] {
        let (rise, over, ss) = host_sim::run::drive::step_response(n, 0.3, seed);
        println!("wheel step 0 -> 0.3 m/s, noise {name:<9}: rise time (10-90 %) {:.0} ms, overshoot {:.1} %, steady-state error {:.2} %", rise * 1e3, over * 100.0, ss * 100.0);
    }
    Ok(())
}
