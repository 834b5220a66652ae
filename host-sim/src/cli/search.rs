//! `host-sim search`: one path.

use std::time::Instant;

use super::args::{parse_cell, AlgoArg, MapArgs};
use host_sim::capacity::new_grid;
use host_sim::report::metrics::polyline_length;
use host_sim::run::engines::Engines;
use robovac::search::prune::prune;
use robovac::Cell;
use serde_json::json;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub map: MapArgs,
    /// Start cell X,Y (column, row from the top).
    #[arg(long, value_parser = parse_cell)]
    pub from: Cell,
    /// Goal cell X,Y.
    #[arg(long, value_parser = parse_cell)]
    pub to: Cell,
    #[arg(long, value_enum, default_value = "oha")]
    pub algo: AlgoArg,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(a: Args) -> Result<(), String> {
    cmd_search(&a.map, a.from, a.to, a.algo, a.json)
}

fn cmd_search(
    args: &MapArgs,
    from: Cell,
    to: Cell,
    algo: AlgoArg,
    json: bool,
) -> Result<(), String> {
    let map = args.load()?;
    let mut grid = new_grid();
    map.to_grid(&mut *grid).map_err(|e| e.to_string())?;
    let mut path = vec![Cell::default(); grid.cells()];
    let engine = algo.engine();
    let mut engines = Engines::new();
    let t0 = Instant::now();
    let r = engines
        .plan(engine, &grid, from, to, &mut path)
        .map_err(|e| format!("{}: {e}", args.map.display()))?;
    let us = t0.elapsed().as_secs_f64() * 1e6;
    let (n, nodes, name) = (r.cells, r.nodes, engine.name());
    let held = r.local_minimum.map(|c| [c.x, c.y]);
    let full = path[..n].to_vec();
    let m = prune(&*grid, &mut path[..n]);
    let pruned = &path[..m];
    let cost = polyline_length(&full);
    let pruned_len = polyline_length(pruned);
    if json {
        let pts = |p: &[Cell]| p.iter().map(|c| json!([c.x, c.y])).collect::<Vec<_>>();
        let out = json!({
            "map": args.map.display().to_string(),
            "algo": name,
            "from": [from.x, from.y],
            "to": [to.x, to.y],
            "path": pts(&full),
            "cost": cost,
            "pruned_path": pts(pruned),
            "pruned_length": pruned_len,
            "nodes_expanded": nodes,
            "reached": held.is_none(),
            "local_minimum": held,
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
        println!("algo            {name}");
        println!("path            {}", fmt(&full));
        println!("cost            {cost:.4} cells ({} cells on the path)", n);
        println!("pruned          {}", fmt(pruned));
        println!("pruned length   {pruned_len:.4} cells ({m} waypoints)");
        println!("nodes expanded  {nodes}");
        if let Some([x, y]) = held {
            println!("ended           held at a local minimum, ({x},{y}), short of the goal");
        }
        println!("time            {us:.1} us");
    }
    Ok(())
}
