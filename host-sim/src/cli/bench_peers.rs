//! `host-sim bench peers`: our A* beside the `pathfinding` crate's
//! ([`host_sim::run::peers`]).

use std::path::Path;

use super::args::MapArgs;
use host_sim::io::scen::parse_scen;
use host_sim::run::peers::run_peers;
use serde_json::json;

/// Runs the comparison and prints it.
pub fn run(scen: &Path, map: &MapArgs, as_json: bool) -> Result<(), String> {
    let bytes = std::fs::read(scen).map_err(|e| format!("{}: cannot read: {e}", scen.display()))?;
    let problems = parse_scen(scen, &bytes).map_err(|e| e.to_string())?;
    let data = map.load()?;
    let rep = run_peers(&data, &problems).map_err(|e| e.to_string())?;
    if as_json {
        let engines: Vec<_> = rep
            .engines
            .iter()
            .map(|e| {
                json!({"name": e.name, "solved": e.solved, "optimal_mismatches": e.optimal_mismatches,
                       "median_us": e.median_us, "total_us": e.total_us})
            })
            .collect();
        let out = json!({"problems": rep.problems, "engines": engines, "ratio": rep.ratio,
                       "jps_ratio": rep.jps_ratio});
        println!("{out}");
        return Ok(());
    }
    println!("scenario {} ({} problems)", scen.display(), rep.problems);
    println!("engine                   solved  mismatches  median us   total ms");
    for e in &rep.engines {
        println!(
            "{:<24} {:>6}  {:>10}  {:>9.1}  {:>9.1}",
            e.name,
            e.solved,
            e.optimal_mismatches,
            e.median_us,
            e.total_us / 1000.0
        );
    }
    println!("pathfinding median / ours (A* octile): {:.2}x", rep.ratio);
    println!(
        "pathfinding median / ours (JPS):       {:.2}x",
        rep.jps_ratio
    );
    Ok(())
}
