//! `host-sim plan`: a complete coverage plan of a map.

use std::path::{Path, PathBuf};

use super::args::{parse_cell, write_file, MapArgs};
use robovac::Cell;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub map: MapArgs,
    /// b-oha, ba, b-theta, b-oha-pc (ours), mark-backtrack, template,
    /// binn, wavefront, stc or bcd.
    #[arg(long, default_value = "b-oha")]
    pub planner: String,
    /// Start cell X,Y (default: the first free cell in reading order).
    #[arg(long, value_parser = parse_cell)]
    pub start: Option<Cell>,
    /// Write the plan as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write a picture of the plan to this file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
}

/// Runs the command.
pub fn run(a: Args) -> Result<(), String> {
    cmd_plan(
        &a.map,
        &a.planner,
        a.start,
        a.json.as_deref(),
        a.svg.as_deref(),
    )
}

fn cmd_plan(
    args: &MapArgs,
    planner: &str,
    start: Option<Cell>,
    json: Option<&Path>,
    svg: Option<&Path>,
) -> Result<(), String> {
    let kind = host_sim::run::plan::planner_by_name(planner).ok_or_else(|| {
        let names = host_sim::run::plan::planner_names();
        format!("unknown planner {planner:?} ({names})")
    })?;
    let map = args.load()?;
    let p = host_sim::run::plan::plan(&map, kind, start)
        .map_err(|e| format!("{}: {e}", args.map.display()))?;
    let m = host_sim::run::plan::metrics_json(&p);
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
        write_file(f, &host_sim::run::plan::plan_json(&map, &p).to_string())?;
    }
    if let Some(f) = svg {
        write_file(
            f,
            &host_sim::report::svg::plan_svg(&map, &p, &args.map.display().to_string()),
        )?;
    }
    Ok(())
}
