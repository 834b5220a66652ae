//! `host-sim scen`: every problem of a MovingAI scenario.

use std::path::{Path, PathBuf};

use super::args::{AlgoArg, MapArgs};
use host_sim::capacity::HostGrid;
use host_sim::io::scen::{parse_scen, run_scen, Problem};
use host_sim::run::engines::{Engine, Engines};
use robovac::Cell;
use serde_json::json;

#[derive(clap::Args)]
pub struct Args {
    /// The .scen file.
    pub scen: PathBuf,
    #[command(flatten)]
    pub map: MapArgs,
    #[arg(long, value_enum, default_value = "astar")]
    pub algo: AlgoArg,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(a: Args) -> Result<(), String> {
    cmd_scen(&a.scen, &a.map, a.algo.engine(), a.json)
}

fn cmd_scen(scen: &Path, args: &MapArgs, engine: Engine, json: bool) -> Result<(), String> {
    let bytes = std::fs::read(scen).map_err(|e| format!("{}: cannot read: {e}", scen.display()))?;
    let problems = parse_scen(scen, &bytes).map_err(|e| e.to_string())?;
    let map = args.load()?;
    let mut engines = Engines::new();
    let plan = |grid: &HostGrid, p: &Problem, path: &mut [Cell]| {
        let r = engines
            .plan(engine, grid, p.start, p.goal, path)
            .map_err(|e| e.to_string())?;
        match r.local_minimum {
            Some(c) => Err(format!("held at a local minimum, ({},{})", c.x, c.y)),
            None => Ok((r.cells, r.nodes)),
        }
    };
    let rep = run_scen(&map, &problems, engine.name(), plan).map_err(|e| e.to_string())?;
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
