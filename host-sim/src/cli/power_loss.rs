//! `mission --power-loss-at S`: the mission cut short by a power loss,
//! then run again from what the robot saved; both runs and the reset's
//! cost on the truth.

use super::mission::Args;
use super::progress;
use host_sim::report::mission::{mission_svg, summary};
use host_sim::run::mission::{report_json, MissionOptions};
use host_sim::run::power_loss::run_power_loss;

/// Runs the two missions and prints them.
pub fn run(a: &Args, opts: &MissionOptions, at_s: f64) -> Result<(), String> {
    let name = a.map.map.display().to_string();
    let pb = progress::status();
    let pl = run_power_loss(opts, at_s, a.save_every, |t, state, cov| {
        pb.set_message(format!(
            "{t:>6.0} s simulated · {state:?} · {:.1} % swept",
            100.0 * cov
        ));
    })
    .map_err(|e| format!("{name}: {e}"))?;
    pb.finish_and_clear();
    let f = &pl.figures;
    println!(
        "mission on {name} ({:?} map, {} people, seed {}), the power cut at {at_s:.0} s (saved every {:.0} s):",
        opts.mode, opts.people, opts.seed, f.saved_every_s
    );
    println!("  before the cut: {}", summary(&pl.first.0));
    println!(
        "  after the reset, from the saved map ({} planning cells clean): {}",
        f.cells_restored,
        summary(&pl.second.0)
    );
    println!(
        "  the reset's cost: floor swept by either run {:.2} % (the first {:.2} %; without the cut {:.2} %); swept again by the second run {:.2} % of the floor; both drove {:.1} m against {:.1} m without the cut: {:.2} % of the floor cleaned again because of the reset",
        100.0 * f.coverage,
        100.0 * f.first_coverage,
        100.0 * f.uninterrupted_coverage,
        100.0 * f.reswept,
        f.distance_m,
        f.uninterrupted_distance_m,
        100.0 * f.extra_cleaned
    );
    if let Some(path) = a.json.as_deref() {
        let v = serde_json::json!({
            "power_loss": f,
            "first": report_json(&pl.first.0),
            "second": report_json(&pl.second.0),
        });
        super::args::write_file(path, &v.to_string())?;
    }
    if let Some(path) = a.svg.as_deref() {
        let (rep, trace, floor) = &pl.second;
        let title = format!("{name} after a power loss at {at_s:.0} s: the second run");
        super::args::write_file(
            path,
            &mission_svg(&opts.map, opts.cell_m, floor, trace, rep, &title),
        )?;
    }
    Ok(())
}
