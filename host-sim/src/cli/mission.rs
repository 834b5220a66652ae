//! `host-sim mission`: a whole cleaning mission in closed loop.

use std::path::{Path, PathBuf};

use super::args::{load_world_map, parse_point, write_file, LocalArg, MapArgs, ModeArg, NoiseArg};
use super::progress;
use host_sim::run::mission::{MissionOptions, MissionTrace};
use host_sim::sim::objects::{parse as parse_object, LowKind, LowObject};
use host_sim::sim::zones::parse_corners;

fn sofa(s: &str) -> Result<LowObject, String> {
    parse_object(LowKind::Sofa, s)
}

fn crossbar(s: &str) -> Result<LowObject, String> {
    parse_object(LowKind::Crossbar, s)
}

fn cable(s: &str) -> Result<LowObject, String> {
    parse_object(LowKind::Cable, s)
}

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub map: MapArgs,
    /// known (a prior map is given) or unknown (mapped while cleaning).
    #[arg(long, value_enum, default_value = "known")]
    pub mode: ModeArg,
    /// People walking about.
    #[arg(long, default_value_t = 0)]
    pub people: usize,
    #[arg(long, value_enum, default_value = "none")]
    pub noise: NoiseArg,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Limit on the simulated cleaning time (charging on the dock does
    /// not count), seconds.
    #[arg(long, default_value_t = 21600.0)]
    pub max_time: f64,
    /// The dock X,Y in metres (default: a free spot near the centre).
    #[arg(long, value_parser = parse_point)]
    pub start: Option<(f64, f64)>,
    /// b-oha, ba, b-theta, b-oha-pc (ours), mark-backtrack, template,
    /// binn, wavefront, stc or bcd.
    #[arg(long, default_value = "b-oha")]
    pub planner: String,
    /// The local planner that steers round what the map does not explain
    /// (people, moved furniture): dwa, or apf (the potential field, for
    /// comparison; its local minima are counted in the JSON and shown by
    /// --events and in the SVG).
    #[arg(long, value_enum, default_value = "dwa")]
    pub local: LocalArg,
    /// Silence the lidar from A to B seconds (A,B) to exercise the fault.
    #[arg(long, value_parser = parse_point)]
    pub lidar_gap: Option<(f64, f64)>,
    /// Add 64 random bytes to every control period's lidar bytes from A to
    /// B seconds (A,B): bursts of garbage on the lidar's UART.
    #[arg(long, value_parser = parse_point)]
    pub lidar_garbage: Option<(f64, f64)>,
    /// Lose one lidar byte in 37 from A to B seconds, as a UART overrun
    /// does (QEMU's USART cannot overrun by itself).
    #[arg(long, value_parser = parse_point)]
    pub lidar_overrun: Option<(f64, f64)>,
    /// With --pil: 32 random bytes and a delimiter on the sim link before
    /// every tick from A to B seconds.
    #[arg(long, value_parser = parse_point)]
    pub link_garbage: Option<(f64, f64)>,
    /// Write the measurements as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write a picture of the mission.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Print the executive's events (state changes, faults, avoidances,
    /// docking) and add them to the JSON.
    #[arg(long)]
    pub events: bool,
    /// Call the executive as the firmware does (control, then planning in
    /// the background) instead of the host's lock-step.
    #[arg(long)]
    pub firmware_order: bool,
    /// Lift the robot at this sim time (seconds) and put it down 1–3 m
    /// away at another heading.
    #[arg(long)]
    pub kidnap: Option<f64>,
    /// Press the robot's button at this sim time (seconds): it stops
    /// cleaning and goes home to the dock.
    #[arg(long)]
    pub home_at: Option<f64>,
    /// Odometry alone: no scan matching (for comparison).
    #[arg(long)]
    pub no_localize: bool,
    /// The bumper disconnected (for comparison): what the lidar cannot
    /// see is found only by stalling against it.
    #[arg(long)]
    pub no_bumper: bool,
    /// No battery gauge (for comparison): the robot cleans for its
    /// 75-minute budget and goes home for good, instead of going home to
    /// charge when its charge runs low and going on after.
    #[arg(long)]
    pub no_battery: bool,
    /// Cut the power at this sim time (seconds), then put the robot back
    /// on its dock and run again from what it saved (its map and which
    /// floor it had cleaned): the second run cleans only what is left.
    /// Prints both runs and the floor cleaned twice because of the reset.
    #[arg(long, value_name = "S")]
    pub power_loss_at: Option<f64>,
    /// With --power-loss-at: how often the robot saves, sim seconds.
    #[arg(long, value_name = "S", default_value_t = 60.0)]
    pub save_every: f64,
    /// The battery's usable energy, Wh (default: the reference robot's
    /// 37.4 Wh pack): a smaller one makes a home need charges.
    #[arg(long, value_name = "WH")]
    pub battery_wh: Option<f64>,
    /// A no-go zone X0,Y0,X1,Y1 (metres, a rectangle's opposite corners;
    /// repeat for more), besides the map's own: the body never enters it.
    #[arg(long = "no-go", value_parser = parse_corners, value_name = "X0,Y0,X1,Y1")]
    pub no_go: Vec<(f64, f64, f64, f64)>,
    /// A virtual wall X0,Y0,X1,Y1 (metres, its ends; repeat for more): the
    /// body never crosses or touches it.
    #[arg(long, value_parser = parse_corners, value_name = "X0,Y0,X1,Y1")]
    pub virtual_wall: Vec<(f64, f64, f64, f64)>,
    /// A sofa X0,Y0,X1,Y1 (metres, opposite corners; repeat for more) in
    /// the twin's world: the lidar's plane passes under its frame, the
    /// body cannot (the bumper finds it).
    #[arg(long, value_parser = sofa, value_name = "X0,Y0,X1,Y1")]
    pub sofa: Vec<LowObject>,
    /// A chair's crossbar X0,Y0,X1,Y1 (metres, its ends), under the
    /// lidar's plane: the body cannot cross it (the bumper finds it).
    #[arg(long, value_parser = crossbar, value_name = "X0,Y0,X1,Y1")]
    pub crossbar: Vec<LowObject>,
    /// A cable or a rug's edge X0,Y0,X1,Y1 (metres, its ends) on the
    /// floor: a wheel driven onto it stalls.
    #[arg(long, value_parser = cable, value_name = "X0,Y0,X1,Y1")]
    pub cable: Vec<LowObject>,
    /// Leave out the map's own no-go zones and virtual walls (a
    /// ValetudoMap's), for comparison.
    #[arg(long)]
    pub no_map_zones: bool,
    /// Save the robot's map here when the mission finishes (the map kept
    /// between runs: the robot's store, as the chip's flash sector holds it).
    #[arg(long, value_name = "FILE")]
    pub save_map: Option<PathBuf>,
    /// Start from the map an earlier run saved: the robot relocalises at
    /// the dock on it, plans over it from the start and keeps it up to
    /// date (`--mode` is then ignored; the floor plan is not given).
    #[arg(long, value_name = "FILE")]
    pub load_map: Option<PathBuf>,
    /// Whose buffers the executive runs in: the host's, or the firmware's
    /// (`fw`: the chip's capacities, so the figures are the robot's).
    #[arg(long, value_enum, default_value_t)]
    pub capacity: host_sim::run::parts::Capacity,
    /// The robot's own map frame, as the robot image keeps it: an empty
    /// map of the capacity's side (12 m at `fw`) with the dock at its
    /// centre, scrolling as the robot nears its edge. For a first run in
    /// unknown mode at `--capacity fw` or `fw16`.
    #[arg(long)]
    pub dock_frame: bool,
    /// With --dock-frame: the map never scrolls (for comparison: the floor
    /// past its edge is lost).
    #[arg(long, requires = "dock_frame")]
    pub no_scroll: bool,
    /// Processor-in-the-loop: run the firmware image built with the
    /// sim-link board (`scripts/pil.sh` builds it) in QEMU's netduinoplus2
    /// instead of the core in this process. Needs qemu-system-arm.
    #[arg(long)]
    pub pil: bool,
    /// The sim-link firmware image for --pil.
    #[arg(
        long,
        default_value = "target/pil/thumbv7em-none-eabihf/release/robovac"
    )]
    pub pil_elf: PathBuf,
    /// Write the firmware's raw defmt log here (--pil); decode it with
    /// `defmt-print -e ELF < FILE`.
    #[arg(long)]
    pub pil_log: Option<PathBuf>,
}

/// Runs the command.
pub fn run(a: Args) -> Result<(), String> {
    let opts = options(&a)?;
    if let Some(at) = a.power_loss_at {
        return super::power_loss::run(&a, &opts, at);
    }
    let trace = cmd_mission(
        &opts,
        &a.map.map.display().to_string(),
        a.json.as_deref(),
        a.svg.as_deref(),
        a.events,
    )?;
    match &a.save_map {
        Some(f) => save_map_file(f, trace),
        None => Ok(()),
    }
}

/// The command line, checked, as the mission's options.
fn options(a: &Args) -> Result<MissionOptions, String> {
    check_times(a)?;
    let kind = host_sim::run::plan::planner_by_name(&a.planner).ok_or_else(|| {
        let names = host_sim::run::plan::planner_names();
        format!("unknown planner {:?} ({names})", a.planner)
    })?;
    use host_sim::run::parts::Capacity;
    if matches!(a.capacity, Capacity::Fw | Capacity::Fw16) && kind.rules().local.needs_field() {
        return Err(format!(
            "planner {} keeps 2 bytes per planning cell, which the firmware's capacity leaves out (use another planner, or the host's capacity)",
            kind.name()
        ));
    }
    if !(a.max_time.is_finite() && a.max_time > 0.0) {
        return Err("--max-time must be a positive number of seconds".into());
    }
    let (mut data, cell_m) = load_world_map(&a.map)?;
    if a.no_map_zones {
        host_sim::sim::zones::drop_map_zones(&mut data);
    }
    Ok(MissionOptions {
        map: data,
        cell_m,
        mode: match a.load_map {
            Some(_) => robovac::mission::MapMode::Unknown,
            None => a.mode.into(),
        },
        people: a.people,
        noise: a.noise.into(),
        seed: a.seed,
        max_time_s: a.max_time,
        start: a.start,
        kind,
        local: a.local.into(),
        lidar_gap_s: a.lidar_gap,
        faults: host_sim::run::inject::Faults {
            lidar_garbage_s: a.lidar_garbage,
            lidar_overrun_s: a.lidar_overrun,
            link_garbage_s: a.link_garbage,
        },
        start_heading: None,
        kidnap_s: a.kidnap,
        home_s: a.home_at,
        localize: !a.no_localize,
        bumper: !a.no_bumper,
        battery: battery_of(a)?,
        zones: zones_of(&a.no_go, &a.virtual_wall),
        objects: [&a.sofa, &a.crossbar, &a.cable]
            .into_iter()
            .flatten()
            .copied()
            .collect(),
        map_store: host_sim::run::mission::MapStore {
            load: a
                .load_map
                .as_deref()
                .map(host_sim::io::store::MemStore::from_file)
                .transpose()?,
            save: a.save_map.is_some(),
            ..Default::default()
        },
        firmware_order: a.firmware_order,
        capacity: a.capacity,
        dock_frame: a.dock_frame,
        scroll: !a.no_scroll,
        pil: a.pil.then(|| host_sim::run::pil::PilOptions {
            elf: a.pil_elf.clone(),
            log: a.pil_log.clone(),
        }),
    })
}

/// The twin's battery as the command line asks.
fn battery_of(a: &Args) -> Result<Option<host_sim::sim::battery::BatterySpec>, String> {
    let mut spec = host_sim::sim::battery::REFERENCE;
    match (a.no_battery, a.battery_wh) {
        (true, Some(_)) => Err("--no-battery and --battery-wh do not go together".into()),
        (true, None) => Ok(None),
        (false, Some(wh)) if !(wh.is_finite() && (0.5..=1000.0).contains(&wh)) => {
            Err("--battery-wh must be between 0.5 and 1000".into())
        }
        (false, wh) => {
            spec.capacity_wh = wh.unwrap_or(spec.capacity_wh);
            Ok(Some(spec))
        }
    }
}

/// The firmware image for `--pil` exists, and the event times are times.
fn check_times(a: &Args) -> Result<(), String> {
    if a.pil && !a.pil_elf.is_file() {
        return Err(format!(
            "--pil: no firmware image at {} (build it with scripts/pil.sh)",
            a.pil_elf.display()
        ));
    }
    if a.kidnap.is_some_and(|t| !(t.is_finite() && t >= 0.0)) {
        return Err("--kidnap must be a time in seconds, 0 or more".into());
    }
    if a.home_at.is_some_and(|t| !(t.is_finite() && t >= 0.0)) {
        return Err("--home-at must be a time in seconds, 0 or more".into());
    }
    if a.power_loss_at.is_some_and(|t| !(t.is_finite() && t > 0.0))
        || !(a.save_every.is_finite() && a.save_every >= 1.0)
    {
        return Err(
            "--power-loss-at and --save-every must be times in seconds (saves 1 s apart at least)"
                .into(),
        );
    }
    if a.power_loss_at.is_some() && (a.pil || a.save_map.is_some()) {
        return Err("--power-loss-at keeps its own saves: not with --pil or --save-map".into());
    }
    Ok(())
}

/// Writes the map the mission saved (`--save-map`) to `f`.
fn save_map_file(f: &Path, trace: MissionTrace) -> Result<(), String> {
    match trace.saved_map {
        Some((store, n)) => {
            std::fs::write(f, store.written())
                .map_err(|e| format!("{}: cannot write: {e}", f.display()))?;
            println!("  map saved to {} ({n} bytes)", f.display());
        }
        None => println!("  map not saved: the mission did not finish"),
    }
    Ok(())
}

/// The command line's zones, in the core's terms.
fn zones_of(
    no_go: &[(f64, f64, f64, f64)],
    walls: &[(f64, f64, f64, f64)],
) -> Vec<robovac::grid::Zone> {
    use host_sim::sim::zones::{no_go_m, wall_m};
    let boxes = no_go.iter().map(|&(a, b, c, d)| no_go_m(a, b, c, d));
    boxes
        .chain(walls.iter().map(|&(a, b, c, d)| wall_m(a, b, c, d)))
        .collect()
}

/// Runs one mission with a progress line on a terminal.
fn cmd_mission(
    opts: &MissionOptions,
    name: &str,
    json: Option<&Path>,
    svg: Option<&Path>,
    events: bool,
) -> Result<MissionTrace, String> {
    use host_sim::report::mission::{events_json, mission_svg, summary};
    use host_sim::run::mission::{report_json, run_mission};
    let pb = progress::status();
    let (rep, trace, floor) = run_mission(opts, |t, state, cov| {
        pb.set_message(format!(
            "{t:>6.0} s simulated · {state:?} · {:.1} % swept",
            100.0 * cov
        ));
    })
    .map_err(|e| format!("{name}: {e}"))?;
    pb.finish_and_clear();
    let map_kind = match opts.map_store.load {
        Some(_) => "the saved".to_string(),
        None => format!("{:?}", opts.mode),
    };
    println!(
        "mission on {name} ({map_kind} map, {} people, seed {}):",
        opts.people, opts.seed
    );
    println!("  {}", summary(&rep));
    if let Some((at_s, (x, y, th))) = trace.kidnap {
        println!(
            "  kidnapped at {at_s:.0} s: put down at ({x:.2}, {y:.2}) m heading {th:.2} rad; {:.1} s lost",
            rep.lost_time_s
        );
    }
    if events {
        for e in &trace.events {
            println!("  {:>8.2} s  {:?}", e.at_us as f64 * 1e-6, e.kind);
        }
    }
    if let Some(f) = json {
        let mut v = report_json(&rep);
        if events {
            v["events"] = events_json(&trace.events);
        }
        if let Some((at_s, (x, y, th))) = trace.kidnap {
            v["kidnap"] =
                serde_json::json!({"at_s": at_s, "put_down_m": [x, y], "heading_rad": th});
        }
        write_file(f, &v.to_string())?;
    }
    if let Some(f) = svg {
        let title = format!(
            "mission on {name}: {:?} map, {} people, noise {:?}, seed {}",
            opts.mode, opts.people, opts.noise, opts.seed
        );
        write_file(
            f,
            &mission_svg(&opts.map, opts.cell_m, &floor, &trace, &rep, &title),
        )?;
    }
    Ok(trace)
}
