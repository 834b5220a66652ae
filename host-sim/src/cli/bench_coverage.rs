//! `host-sim bench coverage`: the coverage planners side by side on real
//! maps (tables per map, a summary, the best per metric marked).

use std::path::{Path, PathBuf};

use host_sim::run::coverage_bench::{self as cb, Row, COLUMNS};
use robovac::coverage::PlannerKind;

use super::args::write_file;
use super::progress;

/// The command's options.
pub struct Opts {
    /// Map files and directories.
    pub maps: Vec<PathBuf>,
    /// Planner names, or `all`.
    pub planners: Vec<String>,
    /// Cell side for image and Valetudo maps, metres.
    pub cell_m: f64,
    /// Write every row as JSON.
    pub json: Option<PathBuf>,
    /// Write one picture per map and planner.
    pub svg_dir: Option<PathBuf>,
}

/// Runs the bench; an error when any plan fails the independent checker.
pub fn run(o: Opts) -> Result<(), String> {
    if !(o.cell_m.is_finite() && o.cell_m > 0.0) {
        return Err("--cell must be a positive number of metres".into());
    }
    let planners = parse_planners(&o.planners)?;
    let files = cb::map_files(&o.maps)?;
    if let Some(d) = &o.svg_dir {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let pb = progress::bar(files.len() * planners.len(), "plans");
    let mut rows: Vec<Row> = Vec::new();
    for f in &files {
        let name = file_name(f);
        let map = cb::load(f, o.cell_m)?;
        let svg = |p: &host_sim::run::plan::Plan| {
            if let Some(d) = &o.svg_dir {
                let title = format!("{name}: {}", p.kind.name());
                let body = host_sim::report::svg::plan_svg(&map, p, &title);
                let out = d.join(svg_name(&name, p.kind.name()));
                let _ = std::fs::write(out, body);
            }
            pb.inc(1);
        };
        rows.extend(cb::bench_map(&name, &map, &planners, svg)?);
    }
    pb.finish_and_clear();
    for f in &files {
        let name = file_name(f);
        let of_map: Vec<&Row> = rows.iter().filter(|r| r.map == name).collect();
        print_map(&name, &of_map);
    }
    print_summary(&rows, &planners);
    if let Some(p) = o.json {
        let doc = serde_json::json!({"cell_m": o.cell_m, "rows": rows});
        write_file(&p, &serde_json::to_string_pretty(&doc).unwrap_or_default())?;
    }
    let failed = rows.iter().filter(|r| !r.valid).count();
    if failed > 0 {
        return Err(format!(
            "{failed} of {} plans failed the independent checker",
            rows.len()
        ));
    }
    Ok(())
}

/// A map's name in the tables and the JSON: its path as given (two maps
/// may share a file name).
fn file_name(f: &Path) -> String {
    f.display().to_string()
}

/// A picture's file name: the map's path with `/` as `_`, then the planner.
fn svg_name(map: &str, planner: &str) -> String {
    format!("{}.{planner}.svg", map.replace(['/', '\\'], "_"))
}

fn parse_planners(names: &[String]) -> Result<Vec<PlannerKind>, String> {
    if names.iter().any(|n| n == "all") {
        return Ok(PlannerKind::ALL.to_vec());
    }
    names
        .iter()
        .map(|n| {
            host_sim::run::plan::planner_by_name(n).ok_or_else(|| {
                let all = host_sim::run::plan::planner_names();
                format!("unknown planner {n:?} ({all}, or all)")
            })
        })
        .collect()
}

/// True when `v` equals the column's best (within rounding).
fn is_best(v: f64, best: f64) -> bool {
    (v - best).abs() <= 1e-9 * best.abs().max(1.0)
}

fn print_map(name: &str, rows: &[&Row]) {
    let Some(r0) = rows.first() else { return };
    let cell = r0
        .cell_m
        .map_or("cells as drawn".into(), |c| format!("{c:.2} m cells"));
    println!(
        "\n{name}: {}x{} ({cell}), {} reachable cells from ({}, {})",
        r0.cells.0, r0.cells.1, r0.metrics.reachable_cells, r0.start.0, r0.start.1
    );
    print!("  {:<15}", "planner");
    for c in &COLUMNS {
        print!(" {:>13}", c.name);
    }
    println!("  checked");
    let bests: Vec<f64> = COLUMNS.iter().map(|c| cb::best(rows, c)).collect();
    for r in rows {
        print!("  {:<15}", r.planner);
        for (c, b) in COLUMNS.iter().zip(&bests) {
            let v = (c.get)(r);
            let mark = if is_best(v, *b) { "*" } else { " " };
            print!(" {:>12.1}{mark}", v);
        }
        let verdict = if r.valid {
            "complete".to_string()
        } else {
            format!("{} missed", r.missed_cells)
        };
        println!("  {verdict}");
    }
}

/// Per planner over all maps: complete plans, mean coverage and repetition,
/// and each other metric as the mean ratio to the best planner of each map;
/// `*` marks the best planner per metric.
fn print_summary(rows: &[Row], planners: &[PlannerKind]) {
    let maps: Vec<&str> = {
        let mut m: Vec<&str> = rows.iter().map(|r| r.map.as_str()).collect();
        m.dedup();
        m
    };
    let score = |k: PlannerKind, ci: usize| -> f64 {
        let c = &COLUMNS[ci];
        let mut sum = 0.0;
        for m in &maps {
            let of_map: Vec<&Row> = rows.iter().filter(|r| r.map == *m).collect();
            let b = cb::best(&of_map, c);
            let v = of_map
                .iter()
                .find(|r| r.planner == k.name())
                .map_or(0.0, |r| (c.get)(r));
            sum += if ci == 0 || ci == 2 {
                v
            } else if b > 0.0 {
                v / b
            } else {
                1.0
            };
        }
        sum / maps.len().max(1) as f64
    };
    println!(
        "\nsummary over {} maps (coverage and repeated: means; other metrics: mean ratio to the map's best):",
        maps.len()
    );
    print!("  {:<15} {:>9}", "planner", "complete");
    for c in &COLUMNS {
        print!(" {:>13}", c.name);
    }
    println!();
    let table: Vec<Vec<f64>> = planners
        .iter()
        .map(|&k| (0..COLUMNS.len()).map(|ci| score(k, ci)).collect())
        .collect();
    for (k, vals) in planners.iter().zip(&table) {
        let done = rows
            .iter()
            .filter(|r| r.planner == k.name() && r.valid)
            .count();
        print!("  {:<15} {:>9}", k.name(), format!("{done}/{}", maps.len()));
        for (ci, v) in vals.iter().enumerate() {
            let col: Vec<f64> = table.iter().map(|t| t[ci]).collect();
            let b = if COLUMNS[ci].lower_is_better {
                col.iter().copied().fold(f64::INFINITY, f64::min)
            } else {
                col.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            };
            let mark = if is_best(*v, b) { "*" } else { " " };
            let prec = if ci == 0 || ci == 2 { 2 } else { 3 };
            print!(" {:>12.prec$}{mark}", v);
        }
        println!();
    }
}
