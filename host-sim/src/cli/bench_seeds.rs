//! `host-sim bench seeds`: the seeds' experiments beside their reported
//! numbers (see [`host_sim::run::seeds`] for each protocol and what we had
//! to decide).

use std::path::PathBuf;

use host_sim::run::seeds::{self, SeedFigures};
use robovac::coverage::PlannerKind;
use robovac::mission::MapMode;
use robovac::Cell;
use serde_json::json;

use super::args::write_file;

/// Runs the three experiments.
pub fn run(json_out: Option<PathBuf>) -> Result<(), String> {
    let s3 = seed003()?;
    let s1 = seed001()?;
    let s2 = seed002()?;
    if let Some(p) = json_out {
        let doc = json!({"seed003": s3, "seed001": s1, "seed002": s2});
        write_file(&p, &serde_json::to_string_pretty(&doc).unwrap_or_default())?;
    }
    Ok(())
}

fn table(rows: &[SeedFigures]) {
    println!(
        "  {:<15} {:>10} {:>12} {:>12} {:>14} {:>11}",
        "planner", "coverage", "repetition", "sub-regions", "backtrack", "first pass"
    );
    for r in rows {
        println!(
            "  {:<15} {:>9.2}% {:>11.2}% {:>12} {:>9.1} cells {:>10.1}%",
            r.planner,
            100.0 * r.coverage,
            100.0 * r.repetition,
            r.sub_regions,
            r.backtrack_cells,
            100.0 * r.first_pass
        );
    }
}

fn all_figures(map: &host_sim::io::maps::MapData, start: Cell) -> Result<Vec<SeedFigures>, String> {
    PlannerKind::ALL
        .iter()
        .map(|&k| seeds::figures(map, k, start))
        .collect()
}

fn seed003() -> Result<Vec<SeedFigures>, String> {
    let map = seeds::map("seed003_20x20.txt", seeds::SEED003_MAP)?;
    println!("seed 003 (§4): 20 x 20 grid, start cell (1, 20) = bottom-left; repetition = repeated cells / (n^2 - obstacles)");
    println!("  paper: regions 100 % coverage, 5.68 % repetition; hybrid method 100 %, 14.45 % (ours: every planner; regions is the seed's)");
    let rows = all_figures(&map, Cell::new(0, 19))?;
    table(&rows);
    Ok(rows)
}

fn seed001() -> Result<serde_json::Value, String> {
    let room = seeds::map("seed001_room12.txt", seeds::SEED001_MAP)?;
    println!("\nseed 001 (§5): 400 x 400 cm room, 33 cm robot = 12 x 12 cells, start top-left");
    println!("  paper: Table 1 (sub-regions, backtracking length, first-pass coverage, repetition) is an image, not in our copy");
    let rows = all_figures(&room, Cell::new(0, 0))?;
    table(&rows);
    let big = seeds::room_for_mission(&room);
    let mut online = Vec::new();
    for kind in [PlannerKind::MarkBacktrack, PlannerKind::BOha] {
        let r = seeds::mission(&big, MapMode::Unknown, 0, kind, 1)?;
        println!(
            "  online (mission, unknown map, 0.11 m cells), {}: coverage {:.1} %, cleaning {:.0} s, finished {}, back at the dock {}",
            kind.name(),
            100.0 * r.coverage,
            r.cleaning_time_s,
            r.finished,
            r.returned_to_start
        );
        online.push(json!({"planner": kind.name(), "coverage": r.coverage,
            "cleaning_time_s": r.cleaning_time_s, "finished": r.finished}));
    }
    Ok(json!({"offline": rows, "online_unknown": online}))
}

fn seed002() -> Result<serde_json::Value, String> {
    let map = seeds::map("seed002_corridors.txt", seeds::SEED002_MAP)?;
    println!(
        "\nseed 002 (§4): 230 m2 corridors, people walking (ours: 2 people, known map, no noise)"
    );
    println!("  paper: 98.3 % coverage, 2.6 % repetition (6 m2 of 230), 2 avoidance events");
    let mut out = Vec::new();
    for kind in [PlannerKind::Template, PlannerKind::BOha] {
        let r = seeds::mission(&map, MapMode::Known, 2, kind, 1)?;
        println!(
            "  {:<9} coverage {:.1} %, repetition {:.1} % (swept area with multiplicity / swept area - 1), {} avoidance events, {} collisions, cleaning {:.0} s",
            kind.name(),
            100.0 * r.coverage,
            100.0 * r.repetition,
            r.avoidance_events,
            r.collisions,
            r.cleaning_time_s
        );
        out.push(
            json!({"planner": kind.name(), "coverage": r.coverage, "repetition": r.repetition,
            "avoidance_events": r.avoidance_events, "collisions": r.collisions}),
        );
    }
    Ok(json!(out))
}
