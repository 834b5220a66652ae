//! `host-sim bench replan`: D* Lite against A* searched again from
//! nothing, on a map that changes while the robot walks
//! ([`host_sim::run::replan`]).

use std::path::Path;

use super::args::MapArgs;
use host_sim::io::scen::parse_scen;
use host_sim::run::replan::{run_replan, Changes, EngineReplans};
use host_sim::run::way_home::way_home_problems;
use serde_json::json;

/// Runs the comparison on the scenario's last `problems` problems (the
/// longest), or with no scenario on `problems` ways home to the map's
/// charger ([`host_sim::run::way_home`]), and prints it.
pub fn run(
    scen: Option<&Path>,
    map: &MapArgs,
    problems: usize,
    how: Changes,
    as_json: bool,
) -> Result<(), String> {
    if problems == 0 || how.every == 0 || how.changes == 0 {
        return Err("--problems, --every and --changes must be at least 1".into());
    }
    if how.side.is_multiple_of(2) || how.side > 15 {
        return Err("--side must be odd and at most 15".into());
    }
    let data = map.load()?;
    let (data, chosen, what) = match scen {
        Some(scen) => {
            let bytes =
                std::fs::read(scen).map_err(|e| format!("{}: cannot read: {e}", scen.display()))?;
            let all = parse_scen(scen, &bytes).map_err(|e| e.to_string())?;
            let last = all[all.len().saturating_sub(problems)..].to_vec();
            (data, last, format!("scenario {}", scen.display()))
        }
        None => {
            let (cspace, ways) = way_home_problems(&data, problems).map_err(|e| e.to_string())?;
            let what = format!("ways home to the charger of {}", map.map.display());
            (cspace, ways, what)
        }
    };
    let mut rep = run_replan(&data, &chosen, how).map_err(|e| e.to_string())?;
    let (d_us, a_us, f_us) = (
        rep.dstar.median_us(),
        rep.astar.median_us(),
        rep.first.median_us(),
    );
    let line = |name: &str, e: &EngineReplans, us: f64| json!({"engine": name, "replans": e.nodes.len(), "mean_nodes": e.mean_nodes(), "median_us": us});
    if as_json {
        let out = json!({
            "problems": rep.problems, "mismatches": rep.mismatches,
            "at_goal": rep.ended[0], "cut_off": rep.ended[1], "all_changes": rep.ended[2],
            "every": how.every, "ahead": how.ahead, "side": how.side,
            "engines": [line("dstar-lite first plan", &rep.first, f_us),
                        line("dstar-lite repair", &rep.dstar, d_us),
                        line("astar-octile from nothing", &rep.astar, a_us)],
        });
        println!("{out}");
        return Ok(());
    }
    println!(
        "{} ({} problems; a {}x{} obstacle {} cells ahead every {} cells walked)",
        what, rep.problems, how.side, how.side, how.ahead, how.every
    );
    println!("engine                       plans  mean nodes  median us");
    for (name, e, us) in [
        ("D* Lite, first plan", &rep.first, f_us),
        ("D* Lite, repair", &rep.dstar, d_us),
        ("A* octile, from nothing", &rep.astar, a_us),
    ] {
        println!(
            "{name:<28} {:>5}  {:>10.1}  {us:>9.1}",
            e.nodes.len(),
            e.mean_nodes()
        );
    }
    println!(
        "problems ended: {} at the goal, {} cut off by an obstacle, {} with every obstacle placed",
        rep.ended[0], rep.ended[1], rep.ended[2]
    );
    println!(
        "cost mismatches {}; A* / D* Lite per replan: nodes {:.2}x, time {:.2}x",
        rep.mismatches,
        rep.astar.mean_nodes() / rep.dstar.mean_nodes().max(1e-9),
        a_us / d_us.max(1e-9)
    );
    Ok(())
}
