//! `host-sim drive`: a route driven by the core's follower while the lidar maps.

use std::path::PathBuf;

use std::time::Instant;

use super::args::{load_world_map, write_file, MapArgs, NoiseArg};
use serde_json::json;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub map: MapArgs,
    /// A route file (`x y` metres per line), `square` (1 m, 10 laps), or
    /// `plan:PLANNER` (a complete coverage plan of the map).
    #[arg(long)]
    pub route: String,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[arg(long, value_enum, default_value = "none")]
    pub noise: NoiseArg,
    /// People walking about.
    #[arg(long, default_value_t = 0)]
    pub people: usize,
    /// Write a picture of the drive.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Write the measurements as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the lidar's bytes to this file.
    #[arg(long)]
    pub capture: Option<PathBuf>,
    /// Flip a bit in this share of the lidar's bytes.
    #[arg(long, default_value_t = 0.0)]
    pub corrupt: f64,
}

/// Runs the command.
pub fn run(a: Args) -> Result<(), String> {
    let Args {
        map: args,
        route,
        seed,
        noise,
        people,
        svg,
        json,
        capture,
        corrupt,
    } = &a;
    let (route, seed, noise, people, corrupt) = (route.as_str(), *seed, *noise, *people, *corrupt);
    let (svg, json, capture) = (svg.as_deref(), json.as_deref(), capture.as_deref());
    use host_sim::run::drive::{drive, drive_svg, parse_route, DriveOptions, Route};
    let (map, cell_m) = load_world_map(args)?;
    let route = if route == "square" {
        Route::Square {
            side_m: 1.0,
            laps: 10,
        }
    } else if let Some(name) = route.strip_prefix("plan:") {
        Route::Plan(
            host_sim::run::plan::planner_by_name(name)
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
        NoiseArg::None => host_sim::sim::robot::Noise::None,
        NoiseArg::Realistic => host_sim::sim::robot::Noise::Realistic,
        NoiseArg::Harsh => host_sim::sim::robot::Noise::Harsh,
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
