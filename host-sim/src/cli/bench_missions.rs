//! `host-sim bench missions`: the mission suite on a thread pool, its table
//! per map, mode and noise, its summary and its JSON.

use std::path::Path;
use std::time::Instant;

use serde_json::json;

use super::args::write_file;
use super::progress;

/// Which missions the suite runs.
pub struct SuiteSelection<'a> {
    pub maps: &'a [&'static str],
    pub people: &'a [usize],
    pub noises: &'a [host_sim::sim::robot::Noise],
    /// The maps' own no-go zones and virtual walls kept.
    pub map_zones: bool,
    /// The local planner that steers the avoidances.
    pub local: robovac::mission::LocalPlanner,
}

/// Map names from the command line (`flats`, `homes` or single names).
pub fn suite_map_names(names: &[String]) -> Result<Vec<&'static str>, String> {
    use host_sim::run::suite::{HOME_MAPS, SUITE_MAPS};
    let mut out = Vec::new();
    for n in names {
        match n.as_str() {
            "flats" => out.extend(SUITE_MAPS.iter().map(|m| m.0)),
            "homes" => out.extend(HOME_MAPS.iter().map(|m| m.0)),
            _ => out.push(
                SUITE_MAPS
                    .iter()
                    .chain(HOME_MAPS.iter())
                    .map(|m| m.0)
                    .find(|m| *m == n)
                    .ok_or_else(|| format!("unknown suite map {n:?}"))?,
            ),
        }
    }
    Ok(out)
}

/// `host-sim bench missions`.
pub fn run(
    runs: usize,
    seed: u64,
    max_time: f64,
    threads: Option<usize>,
    json: Option<&Path>,
    sel: &SuiteSelection<'_>,
) -> Result<(), String> {
    use host_sim::run::suite::{run_suite, suite_cases};
    if runs == 0 {
        return Err("--runs must be at least 1".into());
    }
    if !(max_time.is_finite() && max_time > 0.0) {
        return Err("--max-time must be a positive number of seconds".into());
    }
    let cases = suite_cases(runs, seed, sel.maps, sel.people, sel.noises);
    let threads = threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let t0 = Instant::now();
    let pb = progress::bar(cases.len(), "missions");
    let results = run_suite(
        &cases,
        max_time,
        threads,
        sel.map_zones,
        sel.local,
        |done, _| {
            pb.set_position(done as u64);
        },
    );
    pb.finish_and_clear();
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
    print_suite_groups(&rows);
    print_suite_summary(&rows);
    for f in &failures {
        println!("error: {f}");
    }
    if let Some(f) = json {
        write_file(f, &suite_json(&rows).to_string())?;
    }
    if !failures.is_empty() {
        return Err(format!("{} missions could not run", failures.len()));
    }
    Ok(())
}

/// The suite's table: one row per map, mode and noise.
fn print_suite_groups(
    rows: &[(
        &host_sim::run::suite::SuiteCase,
        &host_sim::run::mission::MissionReport,
    )],
) {
    println!(
        "{:<7} {:<8} {:<10} {:>3} {:>8} {:>8} {:>6} {:>6} {:>6} {:>6} {:>9} {:>9} {:>6} {:>5} {:>6} {:>6} {:>7} {:>7}",
        "map",
        "mode",
        "noise",
        "n",
        "finished",
        "docked",
        "rms mm",
        "max mm",
        "rms °",
        "max °",
        "cover avg",
        "cover min",
        "repet",
        "coll",
        "people",
        "avoid",
        "t/area",
        "sim×"
    );
    let mut groups: Vec<(String, String, String)> = Vec::new();
    for (c, _) in rows {
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
        let sel: Vec<&host_sim::run::mission::MissionReport> = rows
            .iter()
            .filter(|(c, _)| {
                c.map == g.0
                    && format!("{:?}", c.mode).to_lowercase() == g.1
                    && format!("{:?}", c.noise).to_lowercase() == g.2
            })
            .map(|(_, r)| *r)
            .collect();
        let n = sel.len() as f64;
        let mean = |f: &dyn Fn(&host_sim::run::mission::MissionReport) -> f64| {
            sel.iter().map(|r| f(r)).sum::<f64>() / n
        };
        let worst = |f: &dyn Fn(&host_sim::run::mission::MissionReport) -> f64| {
            sel.iter().map(|r| f(r)).fold(0.0, f64::max)
        };
        println!(
            "{:<7} {:<8} {:<10} {:>3} {:>8} {:>8} {:>6.1} {:>6.1} {:>6.2} {:>6.2} {:>8.2}% {:>8.2}% {:>6.2} {:>5} {:>6} {:>6.1} {:>7.2} {:>7.0}",
            g.0,
            g.1,
            g.2,
            sel.len(),
            sel.iter().filter(|r| r.finished).count(),
            sel.iter().filter(|r| r.docked).count(),
            worst(&|r| r.pose_error_rms_mm),
            worst(&|r| r.pose_error_max_mm),
            worst(&|r| r.heading_error_rms_mrad).to_degrees() / 1000.0,
            worst(&|r| r.heading_error_max_mrad).to_degrees() / 1000.0,
            100.0 * mean(&|r| r.coverage),
            100.0 * sel.iter().map(|r| r.coverage).fold(1.0, f64::min),
            mean(&|r| r.repetition),
            sel.iter().map(|r| r.collisions).sum::<usize>(),
            sel.iter().map(|r| r.person_contacts).sum::<usize>(),
            mean(&|r| r.avoidance_events as f64),
            mean(&|r| r.cleaning_time_s / r.floor_time_s.max(1e-9)),
            mean(&|r| r.sim_time_s / r.wall_time_s.max(1e-9)),
        );
    }
}

/// Collisions, the noise-none coverage and the simulator's speed.
fn print_suite_summary(
    rows: &[(
        &host_sim::run::suite::SuiteCase,
        &host_sim::run::mission::MissionReport,
    )],
) {
    let total_coll: usize = rows.iter().map(|(_, r)| r.collisions).sum();
    println!(
        "collisions (the robot moving into something): {total_coll} over {} missions",
        rows.len()
    );
    let minima: u32 = rows.iter().map(|(_, r)| r.counters.apf_minima).sum();
    if minima > 0 {
        println!("local minima of the potential field (--local apf): {minima}");
    }
    for (mode, label) in [
        (robovac::mission::MapMode::Known, "known"),
        (robovac::mission::MapMode::Unknown, "unknown"),
    ] {
        let sel: Vec<_> = rows
            .iter()
            .filter(|(c, _)| c.mode == mode && c.noise == host_sim::sim::robot::Noise::None)
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
}

/// Every mission's report with its configuration.
fn suite_json(
    rows: &[(
        &host_sim::run::suite::SuiteCase,
        &host_sim::run::mission::MissionReport,
    )],
) -> serde_json::Value {
    use host_sim::run::mission::report_json;
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
    serde_json::Value::Array(arr)
}
