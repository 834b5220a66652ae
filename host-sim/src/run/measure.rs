//! A mission's measurements on the truth: every control period (time per
//! state, floor swept, clearances, the pose estimate's error) and at its
//! end (the report's closing fields and its faults).

use super::executive::Executive;
use super::mission::{LidarParser, MissionReport, MissionTrace};
use crate::sim::floor::Floor;
use crate::sim::robot::{RobotConfig, Sim};
use robovac::mission::State;

/// Truth measurements after a period: time per state, floor swept,
/// clearances, where avoidances started.
pub(crate) fn measure(
    sim: &Sim,
    mission: &dyn Executive,
    floor: &mut Floor,
    rep: &mut MissionReport,
    trace: &mut MissionTrace,
    r: f64,
) {
    let key = match mission.state() {
        State::Failed(_) => "Failed".to_string(),
        s => format!("{s:?}"),
    };
    *rep.state_time_s.entry(key).or_insert(0.0) += sim.cfg.control_period_us as f64 * 1e-6;
    let (x, y, _) = sim.pose;
    floor.sweep(x, y);
    pose_error(sim, mission, rep, trace);
    let wall = sim.world.wall_distance(x, y, 1.0) - r;
    rep.min_wall_clearance_m = rep.min_wall_clearance_m.min(wall);
    let person = sim
        .world
        .people
        .iter()
        .map(|p| (p.pos.0 - x).hypot(p.pos.1 - y) - p.radius_m - r)
        .fold(f64::INFINITY, f64::min);
    rep.min_clearance_m = rep.min_clearance_m.min(wall.min(person));
    if let Some(z) = rep.zones.as_mut() {
        z.note(sim.world.zone_intrusion(x, y, r));
    }
    let c = mission.counters();
    if c.avoidance_events as usize > trace.avoidances.len() {
        trace.avoidances.push((x, y));
    }
}

/// The estimate against the truth, accumulated every period.
fn pose_error(
    sim: &Sim,
    mission: &dyn Executive,
    rep: &mut MissionReport,
    trace: &mut MissionTrace,
) {
    if mission.state() == State::SelfTest {
        // Measured from the start of cleaning: the self-test's first
        // revolution relocalises the dock pose a person gave within
        // ±0.2 m and ±15°.
        return;
    }
    let (x, y, th) = sim.pose;
    let p = mission.pose();
    let d = (x * 1000.0 - p.x_mm as f64).hypot(y * 1000.0 - p.y_mm as f64);
    let e = th * 1000.0 - p.theta_mrad as f64;
    let e = (e + std::f64::consts::PI * 1000.0).rem_euclid(std::f64::consts::TAU * 1000.0)
        - std::f64::consts::PI * 1000.0;
    rep.err_sq.0 += d * d;
    rep.err_sq.1 += e * e;
    rep.err_sq.2 += 1;
    rep.pose_error_max_mm = rep.pose_error_max_mm.max(d);
    rep.heading_error_max_mrad = rep.heading_error_max_mrad.max(e.abs());
    if mission.lost() {
        rep.lost_time_s += sim.cfg.control_period_us as f64 * 1e-6;
    }
    if sim.t_us.is_multiple_of(100_000) {
        trace
            .estimate
            .push((p.x_mm as f64 / 1000.0, p.y_mm as f64 / 1000.0));
    }
}

/// The report's end-of-mission fields.
pub(crate) fn finish_report(
    rep: &mut MissionReport,
    mission: &dyn Executive,
    sim: &Sim,
    floor: &Floor,
    (sx, sy, start_heading): (f64, f64, f64),
    cfg: &RobotConfig,
) {
    let start = (sx, sy);
    let r = cfg.diameter_m / 2.0;
    let state = mission.state();
    let c = mission.counters();
    rep.finished = state == State::Done;
    let (x, y, th) = sim.pose;
    rep.returned_to_start = (x - start.0).hypot(y - start.1) < 0.15;
    rep.dock_error_mm = (x - start.0).hypot(y - start.1) * 1000.0;
    let dh = super::drive::wrap(th - start_heading);
    rep.dock_heading_error_mrad = dh.abs() * 1000.0;
    rep.docked = rep.dock_error_mm <= 50.0 && rep.dock_heading_error_mrad <= 52.4;
    let n = rep.err_sq.2.max(1) as f64;
    rep.pose_error_rms_mm = (rep.err_sq.0 / n).sqrt();
    rep.heading_error_rms_mrad = (rep.err_sq.1 / n).sqrt();
    rep.localization = mission.loc_stats();
    let ps = mission.parser_stats();
    rep.lidar_parser = LidarParser {
        frames: ps.frames,
        crc_failures: ps.crc_failures,
        rejected: ps.rejected,
        bytes_skipped: ps.bytes_skipped,
    };
    rep.coverage = floor.coverage();
    rep.distance_m = sim.distance_m;
    let swept = floor.swept_area_m2().max(1e-9);
    rep.repetition = (rep.distance_m * cfg.diameter_m + std::f64::consts::PI * r * r) / swept - 1.0;
    rep.collisions = sim
        .collisions
        .iter()
        .filter(|c| !c.by_person && !c.unseen)
        .count();
    rep.bumper_contacts = sim.collisions.iter().filter(|c| c.unseen).count();
    rep.person_contacts = sim.collisions.iter().filter(|c| c.by_person).count();
    rep.avoidance_events = c.avoidance_events;
    rep.sim_time_s = sim.t_us as f64 * 1e-6;
    rep.ideal_time_s = rep.distance_m / cfg.clean_speed_m_s;
    let (res, _, _) = floor.dims();
    rep.floor_m2 = floor.floor_cells as f64 * res * res;
    rep.floor_time_s = rep.floor_m2 / (cfg.diameter_m * cfg.clean_speed_m_s);
    rep.final_state = format!("{state:?}");
    rep.counters = c;
    rep.charges = c.charges;
    let pose = mission.pose();
    rep.odometry_error_mm =
        (x - pose.x_mm as f64 / 1000.0).hypot(y - pose.y_mm as f64 / 1000.0) * 1000.0;
    rep.faults = faults(&c, state, rep.finished);
    if rep.min_clearance_m.is_infinite() {
        rep.min_clearance_m = 0.0;
    }
}

/// Faults and notable events, counted.
fn faults(c: &robovac::mission::Counters, state: State, finished: bool) -> Vec<(String, u64)> {
    let mut faults = vec![
        ("lidar_silences".to_string(), c.lidar_silences as u64),
        ("stalls".to_string(), c.stalls as u64),
        ("blocked_cells".to_string(), c.blocked_cells as u64),
        ("skipped_subpaths".to_string(), c.skipped as u64),
    ];
    if c.battery_returns > 0 {
        faults.push(("battery: cleaning cut short".to_string(), 1));
    }
    if let State::Failed(f) = state {
        faults.push((format!("failed: {}", f.as_str()), 1));
    }
    if !finished && !matches!(state, State::Failed(_)) {
        faults.push(("time limit".to_string(), 1));
    }
    faults
}
