//! `host-sim mission`: the core's mission executive in closed loop with the
//! physics, at the firmware's rates (wheel control every 10 ms, planning
//! every 100 ms inside it, lidar bytes as the UART delivers them), measured
//! against the ground truth.

use std::time::Instant;

use super::executive::{Executive, Native, Sensors};
use super::measure::{finish_report, measure};
pub use super::report_json::report_json;

use robovac::capacity::{home12, home16};
use robovac::coverage::PlannerKind;
use robovac::grid::Zone;
use robovac::mission::{MapMode, Mission, MissionConfig, MissionParts, MotorCmd, State};
use robovac::robot::hal::{BumperSwitches, ByteSource, MotorDriver};

use crate::io::maps::MapData;
use crate::io::store::MemStore;
use crate::sim::floor::Floor;
use crate::sim::robot::{Noise, RobotConfig, Sim, MOUNT};
use crate::sim::world::World;

pub use super::dock::{default_start, docked_pose};
use super::dock::{given_dock, place_dock};
use super::mission_map::{check_dock_frame, dock_frame, pil_on, prepare_map};
pub use super::mission_map::{MapStore, ZoneFigures, ZONE_MARGIN_M};
pub use super::parts::Capacity;
use super::parts::{Fw16HostParts, FwHostParts, HostParts};
use super::power_loss::{keep_progress, power_cut};

/// Evidence (and fine planning) cell side, mm.
pub const EVIDENCE_MM: u32 = 50;

/// What to run.
#[derive(Clone, Debug)]
pub struct MissionOptions {
    /// The floor (ground truth; in known mode also the robot's prior map).
    pub map: MapData,
    /// Metres per map cell.
    pub cell_m: f64,
    /// Map mode.
    pub mode: MapMode,
    /// People walking.
    pub people: usize,
    /// Noise.
    pub noise: Noise,
    /// Seed.
    pub seed: u64,
    /// Limit on the simulated cleaning time (charging not counted), s.
    pub max_time_s: f64,
    /// The dock (start), m; default: a free spot near the map's centre.
    pub start: Option<(f64, f64)>,
    /// Coverage planner.
    pub kind: PlannerKind,
    /// The local planner that steers an avoidance.
    pub local: robovac::mission::LocalPlanner,
    /// Silence the lidar between these sim times (s), to exercise the fault.
    pub lidar_gap_s: Option<(f64, f64)>,
    /// Bad input on the wire: garbage and overruns in the lidar stream,
    /// garbage on the sim link ([`super::inject`]).
    pub faults: super::inject::Faults,
    /// The dock's heading (the robot's at the start), rad; default: the
    /// map's dock angle, or east.
    pub start_heading: Option<f64>,
    /// Lift the robot at this sim time (s) and put it down 1–3 m away.
    pub kidnap_s: Option<f64>,
    /// Press the robot's button at this sim time (s): go home.
    pub home_s: Option<f64>,
    /// Scan matching on (off: odometry alone, for comparison).
    pub localize: bool,
    /// Call the executive as the firmware does: `control` every period and
    /// then `plan` when due, so a plan's decision reaches the motors one
    /// period later. Off: the lock-step `tick` (plan between sensing and
    /// acting), the order every reported figure was measured in.
    pub firmware_order: bool,
    /// Whose buffers the executive runs in.
    pub capacity: Capacity,
    /// The robot's own map frame, as the robot image keeps it: an empty
    /// map of the capacity's side with the dock at its centre, which
    /// scrolls as the robot nears its edge ([`robovac::mission::scroll`]).
    /// Unknown mode at the firmware's capacity. Off: the map is sized to
    /// the world and holds the whole home from the start.
    pub dock_frame: bool,
    /// With `dock_frame`: the map scrolls (off for comparison: the floor
    /// past the map's edge is then lost).
    pub scroll: bool,
    /// Run the firmware image in the emulator instead of the core in this
    /// process (processor-in-the-loop; at the firmware's capacity).
    pub pil: Option<super::pil::PilOptions>,
    /// The twin's bumper reaches the executive (false: disconnected, for
    /// comparison: the robot then learns of what its lidar cannot see
    /// only by stalling against it).
    pub bumper: bool,
    /// No-go zones and virtual walls given besides the map's own (the
    /// command line's `--no-go` and `--virtual-wall`).
    pub zones: Vec<Zone>,
    /// The map kept between runs.
    pub map_store: MapStore,
    /// The twin's battery and its gauge (None: none; the executive
    /// keeps to its time budget, as with `--pil`).
    pub battery: Option<crate::sim::battery::BatterySpec>,
    /// Things the lidar cannot see, put in the twin's world (the command
    /// line's `--sofa`, `--crossbar`, `--cable`).
    pub objects: Vec<crate::sim::objects::LowObject>,
}

impl MissionOptions {
    /// A mission of the usual kind on `map` (its own cell size, else
    /// 0.1 m): B-OHA*, localisation, the bumper and the reference
    /// battery on, 3 hours of cleaning at most, docked where the map says, no faults, zones or saved map.
    pub fn new(map: MapData, mode: MapMode, people: usize, noise: Noise, seed: u64) -> Self {
        Self {
            cell_m: map.cell_m.unwrap_or(0.1),
            map,
            mode,
            people,
            noise,
            seed,
            max_time_s: 10800.0,
            start: None,
            kind: PlannerKind::BOha,
            local: Default::default(),
            lidar_gap_s: None,
            faults: Default::default(),
            start_heading: None,
            kidnap_s: None,
            home_s: None,
            localize: true,
            firmware_order: false,
            capacity: Default::default(),
            dock_frame: false,
            scroll: true,
            pil: None,
            bumper: true,
            zones: Vec::new(),
            map_store: Default::default(),
            battery: Some(crate::sim::battery::REFERENCE),
            objects: Vec::new(),
        }
    }
}

/// What a mission measured (its JSON: these fields, plus `sim_speed` and
/// `time_vs_ideal`; see [`report_json`]).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct MissionReport {
    /// The executive reached Done.
    pub finished: bool,
    /// With a lidar silence (`lidar_gap_s`): how long after it began the
    /// true robot stood still, ms (None: it never did).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub silence_stop_ms: Option<u64>,
    /// Bad input injected ([`super::inject`]).
    pub injected: super::inject::Injected,
    /// What the executive's lidar parser saw.
    pub lidar_parser: LidarParser,
    /// The true final position is within 0.15 m of the start.
    pub returned_to_start: bool,
    /// Share of the reachable floor swept (truth, 5 cm cells).
    pub coverage: f64,
    /// Swept area counted with multiplicity over the area swept, minus 1:
    /// (distance × cleaning width + body disc) / swept area − 1.
    pub repetition: f64,
    /// The robot moved into a wall or person its lidar could see.
    pub collisions: usize,
    /// The robot moved into something its lidar cannot see (dark
    /// furniture, glass): felt by the bumper. Left out when 0.
    #[serde(skip_serializing_if = "super::report_json::is_zero_usize")]
    pub bumper_contacts: usize,
    /// A person walked into the robot.
    pub person_contacts: usize,
    /// People asked for who found no loop to walk on this map
    /// ([`crate::sim::world::World::add_people`]) and were left out. Left
    /// out when 0.
    #[serde(skip_serializing_if = "super::report_json::is_zero_usize")]
    pub people_missing: usize,
    /// Smallest true gap between the body and a wall or person, m.
    pub min_clearance_m: f64,
    /// Smallest true gap between the body and a wall, m.
    pub min_wall_clearance_m: f64,
    /// Distance driven (truth), m.
    pub distance_m: f64,
    /// Avoidances started.
    pub avoidance_events: u32,
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Simulated time less the time charging on the dock, s.
    pub cleaning_time_s: f64,
    /// Time charging on the dock, s.
    pub charging_time_s: f64,
    /// Charges: home with the battery low, charged, and on again.
    pub charges: u32,
    /// Times the map scrolled under the robot (`--dock-frame`; absent
    /// when it never did).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub map_scrolls: Option<u32>,
    /// The rooms: found, entered, and their agreement with the vendor's
    /// segments (None: no room tour).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rooms: Option<super::rooms::RoomFigures>,
    /// The twin's battery (None: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub battery: Option<super::power::BatteryFigures>,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
    /// Path length ÷ cleaning speed, s.
    pub ideal_time_s: f64,
    /// Reachable floor ÷ (cleaning width × cleaning speed), s.
    pub floor_time_s: f64,
    /// Reachable floor, m².
    pub floor_m2: f64,
    /// The final state.
    pub final_state: String,
    /// Faults and events: (name, count).
    #[serde(serialize_with = "super::report_json::faults_json")]
    pub faults: Vec<(String, u64)>,
    /// The executive's counters.
    #[serde(serialize_with = "super::report_json::counters_json")]
    pub counters: robovac::mission::Counters,
    /// Odometry error at the end, mm.
    pub odometry_error_mm: f64,
    /// The estimated pose against the truth, every control period from
    /// the end of the self-test (whose first revolution relocalises the
    /// given dock pose): RMS position error, mm.
    pub pose_error_rms_mm: f64,
    /// Largest position error, mm.
    pub pose_error_max_mm: f64,
    /// RMS heading error, mrad.
    pub heading_error_rms_mrad: f64,
    /// Largest heading error, mrad.
    pub heading_error_max_mrad: f64,
    /// Back at the true dock within 50 mm and 3° (52 mrad) of the pose it
    /// left from.
    pub docked: bool,
    /// The true final position's distance from the true dock, mm.
    pub dock_error_mm: f64,
    /// The true final heading's difference from the start's, mrad.
    pub dock_heading_error_mrad: f64,
    /// Localisation's counters.
    #[serde(serialize_with = "super::report_json::loc_json")]
    pub localization: robovac::localize::LocStats,
    /// Sim time the robot spent lost (braked, relocalising), s.
    pub lost_time_s: f64,
    #[serde(skip)]
    pub(crate) err_sq: (f64, f64, u64),
    /// Simulated time spent in each state, s.
    pub state_time_s: std::collections::BTreeMap<String, f64>,
    /// The owner's no-go zones and virtual walls, kept to or not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zones: Option<ZoneFigures>,
    /// What the lidar cannot see under or over its plane, and its cost.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub objects: Option<crate::sim::objects::ObjectFigures>,
    /// Processor-in-the-loop: what the firmware measured on itself.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub firmware: Option<super::pil::FirmwareFigures>,
}

/// The lidar parser's counters, as reported.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct LidarParser {
    /// Frames accepted.
    pub frames: u32,
    /// Frames whose checksum failed.
    pub crc_failures: u32,
    /// Frames with a good checksum and implausible content.
    pub rejected: u32,
    /// Bytes skipped looking for a frame's start.
    pub bytes_skipped: u32,
}

/// Tracks for the picture.
#[derive(Clone, Debug, Default)]
pub struct MissionTrace {
    /// True positions (every 10 ms), m.
    pub truth: Vec<(f64, f64)>,
    /// People's tracks.
    pub people: Vec<Vec<(f64, f64)>>,
    /// Where avoidances started.
    pub avoidances: Vec<(f64, f64)>,
    /// Collisions: (where, by a person).
    pub collisions: Vec<((f64, f64), bool)>,
    /// Start, m.
    pub start: (f64, f64),
    /// The executive's events, in order.
    pub events: Vec<robovac::mission::Event>,
    /// The estimated positions (every 100 ms), m.
    pub estimate: Vec<(f64, f64)>,
    /// The kidnap: when (s) and where the robot was put down (m, m, rad).
    pub kidnap: Option<(f64, (f64, f64, f64))>,
    /// The owner's no-go zones and virtual walls.
    pub zones: Vec<Zone>,
    /// Things the lidar cannot see ([`crate::sim::objects`]).
    pub objects: Vec<crate::sim::objects::LowObject>,
    /// Where a wheel ran onto a cable and stalled, m.
    pub snags: Vec<(f64, f64)>,
    /// The map saved at the end ([`MapStore::save`]), or the last map and
    /// progress saved ([`MapStore::progress_every_s`]), and its bytes.
    pub saved_map: Option<(MemStore, u32)>,
    /// Cells a restored progress marked clean: planning cells, and the
    /// edge pass's contour cells.
    pub restored_cells: u32,
    /// The rooms the executive found (known mode).
    pub rooms: Option<super::rooms::RoomView>,
}

/// Runs a mission; `progress(sim_s, state, coverage)` is called about
/// every simulated 10 s.
pub fn run_mission(
    opts: &MissionOptions,
    progress: impl FnMut(f64, State, f64),
) -> Result<(MissionReport, MissionTrace, Floor), String> {
    let t0 = Instant::now();
    let cfg = RobotConfig::default();
    let r = cfg.diameter_m / 2.0;
    let mut world = World::new(opts.map.clone(), opts.cell_m);
    world.zones = crate::sim::zones::map_zones(&opts.map);
    world.zones.extend_from_slice(&opts.zones);
    crate::sim::objects::place(&mut world, &opts.objects)?;
    let (start, dock_heading) = place_dock(opts, &mut world, r)?;
    let heading = opts.start_heading.unwrap_or(dock_heading);
    let pose = (start.0, start.1, heading);
    let mut sim = Sim::new(cfg.clone(), world, pose, opts.noise, opts.seed);
    let mut floor = Floor::new(&sim.world, start, r, 0.05);
    let mut mission = Box::new(Mission::new(mission_config(opts, &cfg, r)));
    check_dock_frame(opts, &sim.world)?;
    if let Some(pil) = &opts.pil {
        if !sim.world.zones.is_empty() {
            return Err(
                "no-go zones and virtual walls do not cross the sim link yet: run without --pil"
                    .into(),
            );
        }
        let cfg = mission_config(opts, &sim.cfg.clone(), r);
        // The prior in the image's capacity (`--capacity fw16` for an
        // image built with `home16`).
        let mut exec = if opts.capacity == Capacity::Fw16 {
            let map = Box::new(home16::FwEvidence::new());
            pil_on(pil, opts, cfg, map, home16::FW_HOME_SIDE, &sim.world, start)?
        } else {
            let map = Box::new(home12::FwEvidence::new());
            pil_on(pil, opts, cfg, map, home12::FW_HOME_SIDE, &sim.world, start)?
        };
        let (mut rep, trace) = drive(opts, &mut sim, &mut floor, &mut exec, pose, progress)?;
        rep.wall_time_s = t0.elapsed().as_secs_f64();
        rep.map_scrolls = opts.dock_frame.then_some(exec.frame.scrolls);
        rep.firmware = exec.report.map(super::pil::FirmwareFigures::from);
        return Ok((rep, trace, floor));
    }
    // The buffers of the capacity asked for, lent to the executive.
    let (mut hp, mut fp, mut fp16, mut host, mut fw, mut fw16);
    let mut frame = super::executive::Frame::default();
    let parts: &mut dyn MissionParts = match opts.capacity {
        Capacity::Host => {
            hp = HostParts::new(opts.kind);
            prepare_map(&mut hp.map, &sim.world, opts)?;
            host = hp.parts();
            &mut host
        }
        Capacity::Fw => {
            fp = FwHostParts::new(opts.kind);
            if opts.dock_frame {
                frame = dock_frame(&mut fp.map, home12::FW_HOME_SIDE, start)?;
            } else {
                prepare_map(&mut fp.map, &sim.world, opts)?;
            }
            fw = fp.parts();
            &mut fw
        }
        Capacity::Fw16 => {
            fp16 = Fw16HostParts::new(opts.kind);
            if opts.dock_frame {
                frame = dock_frame(&mut fp16.map, home16::FW_HOME_SIDE, start)?;
            } else {
                prepare_map(&mut fp16.map, &sim.world, opts)?;
            }
            fw16 = fp16.parts();
            &mut fw16
        }
    };
    let mut exec = Native {
        mission: &mut mission,
        parts,
        firmware_order: opts.firmware_order,
        frame,
    };
    let (mut rep, mut trace) = drive(opts, &mut sim, &mut floor, &mut exec, pose, progress)?;
    rep.wall_time_s = t0.elapsed().as_secs_f64();
    rep.map_scrolls = opts.dock_frame.then_some(exec.frame.scrolls);
    let cell_mm = mission_config(opts, &cfg, r).plan_cell_mm;
    let map_h_m = super::rooms::evidence_h_m(sim.world.size_m().1, EVIDENCE_MM);
    trace.rooms = super::rooms::RoomView::of(&*exec.parts, cell_mm, map_h_m);
    rep.rooms = super::rooms::RoomFigures::of(&opts.map, trace.rooms.as_ref(), &rep.counters);
    Ok((rep, trace, floor))
}

/// The mission's loop with the executive given, until it ends or time is
/// up.
pub(crate) fn drive(
    opts: &MissionOptions,
    sim: &mut Sim,
    floor: &mut Floor,
    mission: &mut dyn Executive,
    pose: (f64, f64, f64),
    mut progress: impl FnMut(f64, State, f64),
) -> Result<(MissionReport, MissionTrace), String> {
    let cfg = sim.cfg.clone();
    let r = cfg.diameter_m / 2.0;
    let start = (pose.0, pose.1);
    mission.begin(given_dock(opts, pose))?;
    mission.debug_grid(false);
    let mut rep = MissionReport {
        zones: ZoneFigures::of(&sim.world.zones),
        min_clearance_m: f64::INFINITY,
        min_wall_clearance_m: f64::INFINITY,
        ..Default::default()
    };
    let mut trace = MissionTrace {
        start,
        zones: sim.world.zones.clone(),
        objects: sim.world.objects.clone(),
        ..Default::default()
    };
    if let (true, Some(store)) = (opts.map_store.restore_progress, &opts.map_store.load) {
        // A progress the robot cannot read (damaged, another map's): it
        // cleans the whole home again, as the robot would.
        trace.restored_cells = mission.restore_progress(&mut store.clone()).unwrap_or(0);
    }
    let dock = given_dock(opts, pose);
    let max_us = (opts.max_time_s * 1e6) as u64;
    let mut next_progress = 10_000_000u64;
    let trace_on = std::env::var_os("ROBOVAC_DEBUG_TRACE").is_some();
    let mut seen_collisions = 0usize;
    let fine = super::mission_debug::fine_window();
    let mut kidnap_us = opts.kidnap_s.map(|t| (t * 1e6) as u64);
    let mut home_us = opts.home_s.map(|t| (t * 1e6) as u64);
    let mut inject = super::inject::Injector::new(opts.faults, opts.seed);
    let mut power = super::power::Power::new(opts.battery, pose);
    // The limit is on cleaning time: charging does not count.
    while sim.t_us < max_us + (charging_s(&rep) * 1e6) as u64 && !mission.finished() {
        if kidnap_us.is_some_and(|t| sim.t_us >= t) {
            kidnap_us = None;
            trace.kidnap = sim.kidnap().map(|p| (sim.t_us as f64 * 1e-6, p));
        }
        if home_us.is_some_and(|t| sim.t_us >= t) {
            home_us = None;
            mission.request_home()?;
        }
        control_period(sim, mission, opts, &mut inject, &mut power)?;
        if power.flat() || power_cut(opts, sim.t_us) {
            break;
        }
        keep_progress(opts, sim.t_us, mission, dock, &mut trace)?;
        while let Some(e) = mission.pop_event() {
            trace.events.push(e);
        }
        if trace_on && sim.collisions.len() > seen_collisions {
            seen_collisions = sim.collisions.len();
            mission.debug_collision(sim);
        }
        measure(sim, mission, floor, &mut rep, &mut trace, r);
        if trace_on && sim.t_us.is_multiple_of(1_000_000) {
            mission.debug_tick(sim);
        }
        if fine.is_some_and(|(a, b)| (a..=b).contains(&sim.t_us)) {
            mission.debug_fine(sim);
        }
        if sim.t_us >= next_progress {
            next_progress += 10_000_000;
            progress(sim.t_us as f64 * 1e-6, mission.state(), floor.coverage());
        }
    }
    progress(sim.t_us as f64 * 1e-6, mission.state(), floor.coverage());
    mission.end()?;
    if opts.map_store.save && mission.finished() {
        let mut store = MemStore::erased();
        let n = mission.save_map(dock, &mut store)?;
        trace.saved_map = Some((store, n));
    }
    mission.debug_grid(true);
    finish_report(&mut rep, mission, sim, floor, pose, &cfg);
    rep.objects = crate::sim::objects::ObjectFigures::of(sim, floor);
    rep.people_missing = opts.people.saturating_sub(sim.world.people.len());
    battery_report(&mut rep, &power);
    trace.truth = std::mem::take(&mut sim.trajectory);
    rep.injected = inject.done;
    rep.silence_stop_ms = opts
        .lidar_gap_s
        .and_then(|g| super::inject::stop_after_silence_ms(&trace.truth, g));
    trace.people = sim.world.people.iter().map(|p| p.track.clone()).collect();
    trace.snags = sim.snags.iter().map(|s| s.1).collect();
    trace.collisions = sim
        .collisions
        .iter()
        .map(|c| (c.pos, c.by_person))
        .collect();
    Ok((rep, trace))
}

/// The battery's figures, and the cleaning time without charging.
fn battery_report(rep: &mut MissionReport, power: &super::power::Power) {
    rep.battery = super::power::BatteryFigures::of(power);
    rep.charging_time_s = charging_s(rep);
    rep.cleaning_time_s = rep.sim_time_s - rep.charging_time_s;
    if power.flat() {
        rep.faults.push(("battery ran flat".to_string(), 1));
    }
}

/// Time the executive has spent charging on the dock, s.
fn charging_s(rep: &MissionReport) -> f64 {
    rep.state_time_s.get("Charging").copied().unwrap_or(0.0)
}

/// The executive's configuration for this robot. Its margins follow its
/// lidar's range noise (the firmware is configured for its sensor; the
/// ideal one has none).
fn mission_config(opts: &MissionOptions, cfg: &RobotConfig, r: f64) -> MissionConfig {
    let mut mcfg = MissionConfig::new(opts.mode, cfg.geometry(), cfg.gains, MOUNT);
    mcfg.kind = opts.kind;
    mcfg.localize = opts.localize;
    mcfg.local = opts.local;
    mcfg.prior_saved = opts.map_store.load.is_some();
    mcfg.scroll_map = opts.dock_frame && opts.scroll;
    mcfg.radius_mm = (r * 1000.0).round() as i32;
    if opts.noise.noisy() {
        mcfg = mcfg.with_lidar_noise((cfg.lidar_noise_m * 1000.0).round() as i32);
    }
    mcfg
}

/// One control period: physics, the lidar bytes that arrived (unless in
/// the requested gap), then the executive's period and the motors.
fn control_period(
    sim: &mut Sim,
    mission: &mut dyn Executive,
    opts: &MissionOptions,
    inject: &mut super::inject::Injector,
    power: &mut super::power::Power,
) -> Result<(), String> {
    let steps = sim.cfg.control_period_us / sim.cfg.physics_step_us;
    for _ in 0..steps {
        sim.step();
    }
    power.step(sim, sim.cfg.control_period_us as f64 * 1e-6);
    let mut buf = [0u8; 512];
    let mut lidar = Vec::new();
    loop {
        let n = sim.read(&mut buf);
        if n == 0 {
            break;
        }
        let t = sim.t_us as f64 * 1e-6;
        let silent = opts.lidar_gap_s.is_some_and(|(a, b)| t >= a && t < b);
        if !silent {
            lidar.extend_from_slice(buf.get(..n).unwrap_or(&[]));
        }
    }
    let t = sim.t_us as f64 * 1e-6;
    inject.lidar(t, &mut lidar);
    let noise = inject.link(t);
    if !noise.is_empty() {
        mission.link_noise(&noise)?;
    }
    let enc = sim.read_encoders();
    let bumper = if opts.bumper {
        sim.read_bumper()
    } else {
        robovac::mission::Bumper::RELEASED
    };
    let sensors = Sensors {
        t_us: sim.t_us,
        lidar: &lidar,
        enc,
        bumper,
        charge_pm: power.gauge_pm(),
    };
    match mission.period(&sensors)? {
        MotorCmd::Duty(a, b) => sim.set_duty(a, b),
        MotorCmd::Brake => sim.brake(),
    }
    Ok(())
}
