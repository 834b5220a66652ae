//! `host-sim drive`: drives a route with the core's wheel controllers and
//! odometry while the lidar maps, and measures both against the truth. Also
//! the wheel step response measurement.

use robovac::nav::follow::{follow, FollowCmd, SubPaths, DEFAULT_FOLLOW};
use robovac::robot::hal::{ByteSource, MotorDriver};
use robovac::robot::lidar::ld06::Ld06;
use robovac::robot::lidar::scan::{Scan, ScanAssembler};
use robovac::robot::lidar::{LidarProtocol, ParserStats};
use robovac::robot::lidar_map::{CellState, EvidenceMap};
use robovac::robot::odometry::{Odometry, Pose};
use robovac::robot::wheel_control::WheelControl;

use crate::capacity::{HOST_EVIDENCE, SCAN_FRAMES};
use crate::io::maps::MapData;
use crate::report::svg::Canvas;
use crate::sim::robot::MOUNT;
use crate::sim::robot::{Noise, RobotConfig, Sim};
use crate::sim::world::World;

/// A route.
#[derive(Clone, Debug)]
pub enum Route {
    /// A square of `side_m`, driven `laps` times counter-clockwise from a
    /// clear spot found automatically.
    Square {
        /// Side, m.
        side_m: f64,
        /// Laps.
        laps: usize,
    },
    /// Waypoints in metres; the robot starts at the first, facing the second.
    Points(Vec<(f64, f64)>),
    /// A complete coverage plan of the known map by this planner, on
    /// robot-sized cells (a cell is free where the body fits at its centre).
    Plan(robovac::coverage::PlannerKind),
}

/// Planner cell side for drives of coverage plans, m.
pub const PLAN_CELL_M: f64 = 0.3;

/// The planner's grid of a world: cells of `PLAN_CELL_M`, free where a
/// disc of `radius_m` at the cell centre touches no wall. Row 0 is the top.
pub fn planner_map(world: &World, radius_m: f64) -> MapData {
    let (wm, hm) = world.size_m();
    let (w, h) = (
        (wm / PLAN_CELL_M).floor() as u32,
        (hm / PLAN_CELL_M).floor() as u32,
    );
    let mut blocked = Vec::with_capacity((w * h) as usize);
    for gy in 0..h {
        for gx in 0..w {
            let (x, y) = cell_centre_m(gx, gy, hm);
            blocked.push(world.disc_hits_wall(x, y, radius_m));
        }
    }
    MapData {
        width: w,
        height: h,
        blocked,
        cell_m: Some(PLAN_CELL_M),
        ..Default::default()
    }
}

/// World position (m) of a planner cell's centre; `hm` the world's height.
pub fn cell_centre_m(gx: u32, gy: u32, hm: f64) -> (f64, f64) {
    (
        (gx as f64 + 0.5) * PLAN_CELL_M,
        hm - (gy as f64 + 0.5) * PLAN_CELL_M,
    )
}

/// Parses a route file: one `x y` pair (metres) per line, `#` comments.
pub fn parse_route(text: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut pts = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| {
                s.parse::<f64>()
                    .map_err(|_| format!("route line {}: {s:?} is not a number", n + 1))
            })
            .collect::<Result<_, _>>()?;
        match v[..] {
            [x, y] if x.is_finite() && y.is_finite() => pts.push((x, y)),
            _ => return Err(format!("route line {}: expected `x y` in metres", n + 1)),
        }
    }
    if pts.len() < 2 {
        return Err("a route needs at least two points".into());
    }
    Ok(pts)
}

/// What a drive measured.
#[derive(Clone, Debug, Default)]
pub struct DriveReport {
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Distance driven (truth), m.
    pub distance_m: f64,
    /// Odometry position error at the end, mm.
    pub final_position_error_mm: f64,
    /// Odometry heading error at the end, mrad.
    pub final_heading_error_mrad: f64,
    /// Largest position error during the run, mm.
    pub max_position_error_mm: f64,
    /// Collisions (the body moving into something).
    pub collisions: usize,
    /// Lidar parser counters.
    pub parser: ParserStats,
    /// Completed scans.
    pub scans: u32,
    /// Evidence cells observed (not unknown).
    pub map_cells_seen: usize,
    /// Share of observed cells whose class matches the truth.
    pub map_correct_share: f64,
    /// Share of truly free observed cells marked occupied.
    pub map_false_obstacle_share: f64,
    /// Share of truly occupied observed cells marked free.
    pub map_false_free_share: f64,
    /// Share of the cells the robot's body swept that the map marks occupied.
    pub path_false_obstacle_rate: f64,
    /// True when every waypoint was reached.
    pub completed: bool,
    /// Waypoints given up after a minute without reaching them.
    pub skipped_waypoints: usize,
    /// Share of the reachable floor the body swept.
    pub floor_coverage: f64,
    /// Waypoints driven.
    pub waypoints: usize,
}

/// Trajectories and map for pictures.
pub struct DriveTrace {
    /// True positions, m.
    pub truth: Vec<(f64, f64)>,
    /// Odometry positions, m.
    pub odom: Vec<(f64, f64)>,
    /// The evidence map.
    pub map: Box<EvidenceMap<HOST_EVIDENCE>>,
    /// Lidar bytes, when captured.
    pub capture: Option<Vec<u8>>,
}

/// Drive options.
pub struct DriveOptions {
    /// The floor.
    pub map: MapData,
    /// Metres per map cell.
    pub cell_m: f64,
    /// The route.
    pub route: Route,
    /// Noise level.
    pub noise: Noise,
    /// Seed.
    pub seed: u64,
    /// People walking.
    pub people: usize,
    /// Record the lidar bytes.
    pub capture: bool,
    /// Inject byte corruption (flip probability per byte).
    pub corrupt: f64,
    /// Evidence cell size, mm.
    pub evidence_mm: u32,
}

/// An angle wrapped to −π..π, rad.
pub(crate) fn wrap(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
}

/// A clear spot for a square of `side` (robot centre path), if any.
fn square_spot(world: &World, side: f64, r: f64) -> Option<(f64, f64)> {
    let (w, h) = world.size_m();
    let mut best: Option<(f64, (f64, f64))> = None;
    let step = 0.05;
    let mut y = r;
    while y + side + r < h {
        let mut x = r;
        while x + side + r < w {
            let c = [(x, y), (x + side, y), (x + side, y + side), (x, y + side)];
            let ok = (0..4).all(|k| world.segment_clear(c[k], c[(k + 1) % 4], r + 0.08));
            if ok {
                let d = (x + side / 2.0 - w / 2.0).hypot(y + side / 2.0 - h / 2.0);
                if best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, (x, y)));
                }
            }
            x += step;
        }
        y += step;
    }
    best.map(|(_, p)| p)
}

/// Runs a drive.
pub fn drive(opts: DriveOptions) -> Result<(DriveReport, DriveTrace), String> {
    let cfg = RobotConfig::default();
    let mut world = World::new(opts.map.clone(), opts.cell_m);
    let r = cfg.diameter_m / 2.0;
    let waypoints = route_waypoints(&opts.route, &world, r)?;
    if waypoints.len() < 2 {
        return Err("the route has fewer than two waypoints".into());
    }
    let start = waypoints[0];
    if world.disc_hits_wall(start.0, start.1, r) {
        return Err(format!(
            "the route starts inside an obstacle at ({:.2}, {:.2}) m",
            start.0, start.1
        ));
    }
    let heading = (waypoints[1].1 - start.1).atan2(waypoints[1].0 - start.0);
    let mut rng = robovac::grid::maps::SplitMix64::new(opts.seed ^ 0x5EED);
    world.add_people(opts.people, &mut rng);
    let pose = (start.0, start.1, heading);
    let mut sim = Sim::new(cfg.clone(), world, pose, opts.noise, opts.seed);
    sim.corruption.flip = opts.corrupt;
    if opts.capture {
        sim.capture = Some(Vec::new());
    }
    // The core's pieces.
    let geom = cfg.geometry();
    let mut odom = Odometry::new(geom);
    odom.set_pose(
        (start.0 * 1000.0) as i32,
        (start.1 * 1000.0) as i32,
        (heading * 1000.0).round() as i32,
    );
    let mut wheels = WheelControl::new(cfg.gains, (cfg.wheelbase_m * 1000.0) as i32);
    let mut parser = Ld06::new();
    let mut asm: Box<ScanAssembler<SCAN_FRAMES>> = Box::new(ScanAssembler::new());
    let mut scan: Box<Scan<SCAN_FRAMES>> = Box::new(Scan::new());
    let mut map: Box<EvidenceMap<HOST_EVIDENCE>> = Box::new(EvidenceMap::new());
    let (wm, hm) = sim.world.size_m();
    let res = opts.evidence_mm.max(10);
    map.reset(
        ((wm * 1000.0) as u32).div_ceil(res),
        ((hm * 1000.0) as u32).div_ceil(res),
        res,
    )
    .map_err(|e| format!("map too large for the lidar map: {e}"))?;
    let um_per_tick = geom.um_per_tick();
    let mut last_ticks = [sim.encoder(0), sim.encoder(1)];
    odom.update(last_ticks[0], last_ticks[1]);
    let mut prev_delta = [0i32; 2];
    let mut rep = DriveReport::default();
    let mut odom_track = Vec::new();
    let max_time_us = 3_600_000_000u64;
    let mut buf = [0u8; 512];
    let mut settle = 0u32;
    let mut waypoint_since_us = 0u64;
    let mut floor = crate::sim::floor::Floor::new(&sim.world, start, r, 0.05);
    let mm = |p: (f64, f64)| ((p.0 * 1000.0).round() as i32, (p.1 * 1000.0).round() as i32);
    let mut queue: Box<SubPaths<64>> = Box::new(SubPaths::new());
    queue.reset(mm(start));
    let mut next_wp = 1usize;
    while sim.t_us < max_time_us {
        for _ in 0..(cfg.control_period_us / cfg.physics_step_us) {
            sim.step();
        }
        // Encoders through the core's trait.
        let (l, rr) = sim.read_encoders();
        let pose: Pose = odom.update(l, rr);
        let d = [
            l.wrapping_sub(last_ticks[0]) as i16 as i32,
            rr.wrapping_sub(last_ticks[1]) as i16 as i32,
        ];
        last_ticks = [l, rr];
        // Speed over the last two periods (20 ms), mm/s.
        let per = cfg.control_period_us as i64;
        let meas =
            [0, 1].map(|i| ((d[i] + prev_delta[i]) as i64 * um_per_tick * 1000 / (2 * per)) as i32);
        prev_delta = d;
        // Route following on the odometry estimate.
        let (px, py) = (pose.x_mm as f64 / 1000.0, pose.y_mm as f64 / 1000.0);
        odom_track.push((px, py));
        // The core's follower on straight sub-paths merged from the route.
        while queue.len() < 60 && next_wp < waypoints.len() {
            queue.push(mm(waypoints[next_wp]), true);
            next_wp += 1;
        }
        let (v_cmd, w_cmd) = match queue.front() {
            Some((seg, _)) => {
                if sim.t_us - waypoint_since_us > 60_000_000 {
                    // Not reached in a minute (blocked): give up on it.
                    rep.skipped_waypoints += 1;
                    queue.pop();
                    waypoint_since_us = sim.t_us;
                    (0, 0)
                } else {
                    match follow(&DEFAULT_FOLLOW, &seg, &pose) {
                        FollowCmd::Arrived => {
                            queue.pop();
                            waypoint_since_us = sim.t_us;
                            (0, 0)
                        }
                        FollowCmd::Drive { v_mm_s, w_mrad_s } => (v_mm_s, w_mrad_s),
                    }
                }
            }
            None => {
                settle += 1;
                (0, 0)
            }
        };
        floor.sweep(sim.pose.0, sim.pose.1);
        let (dl, dr) = wheels.step(
            v_cmd,
            w_cmd,
            meas[0],
            meas[1],
            d[0] != 0,
            d[1] != 0,
            cfg.control_period_us as u32,
        );
        if wheels.fault().is_some() {
            sim.brake();
            wheels.clear_fault();
        } else {
            sim.set_duty(dl, dr);
        }
        // Lidar bytes through the core's parser into scans and the map.
        loop {
            let n = sim.read(&mut buf);
            if n == 0 {
                break;
            }
            for &b in &buf[..n] {
                if let Some(f) = parser.feed(b) {
                    if asm.push(&f, pose, &mut scan) {
                        map.integrate_scan(&scan, &MOUNT);
                    }
                }
            }
        }
        let err = (sim.pose.0 - px).hypot(sim.pose.1 - py) * 1000.0;
        rep.max_position_error_mm = rep.max_position_error_mm.max(err);
        if settle > 50 {
            break;
        }
    }
    rep.completed = queue.is_empty() && next_wp >= waypoints.len() && rep.skipped_waypoints == 0;
    rep.floor_coverage = floor.coverage();
    rep.waypoints = waypoints.len();
    let pose = odom.pose();
    rep.sim_time_s = sim.t_us as f64 * 1e-6;
    rep.distance_m = sim.distance_m;
    rep.final_position_error_mm = (sim.pose.0 - pose.x_mm as f64 / 1000.0)
        .hypot(sim.pose.1 - pose.y_mm as f64 / 1000.0)
        * 1000.0;
    rep.final_heading_error_mrad =
        wrap(sim.pose.2 - pose.theta_mrad as f64 / 1000.0).abs() * 1000.0;
    rep.collisions = sim.collisions.iter().filter(|c| !c.by_person).count();
    rep.parser = parser.stats();
    rep.scans = asm.scans;
    map_accuracy(&map, &sim.world, &mut rep);
    rep.path_false_obstacle_rate = path_false_obstacles(&map, &sim.trajectory, r);
    let trace = DriveTrace {
        truth: sim.trajectory.clone(),
        odom: odom_track,
        map,
        capture: sim.capture.take(),
    };
    Ok((rep, trace))
}

/// The route's waypoints (m): a square placed clear of walls, the given
/// points, or a complete coverage plan of the map.
fn route_waypoints(route: &Route, world: &World, r: f64) -> Result<Vec<(f64, f64)>, String> {
    Ok(match route {
        Route::Square { side_m, laps } => {
            let (x, y) =
                square_spot(world, *side_m, r).ok_or("no clear spot for the square on this map")?;
            let mut v = vec![(x, y)];
            for _ in 0..*laps {
                v.extend([
                    (x + side_m, y),
                    (x + side_m, y + side_m),
                    (x, y + side_m),
                    (x, y),
                ]);
            }
            v
        }
        Route::Points(p) => p.clone(),
        Route::Plan(kind) => {
            let pm = planner_map(world, r + 0.01);
            let plan = crate::run::plan::plan(&pm, *kind, None)?;
            let hm = world.size_m().1;
            plan.waypoints
                .iter()
                .map(|c| cell_centre_m(c.x as u32, c.y as u32, hm))
                .collect()
        }
    })
}

/// The map's accuracy against the truth: cells seen, classified correctly,
/// false obstacles and false free space.
fn map_accuracy(map: &EvidenceMap<HOST_EVIDENCE>, world: &World, rep: &mut DriveReport) {
    let (mut seen, mut correct, mut free_seen, mut false_obs, mut occ_seen, mut false_free) =
        (0usize, 0usize, 0usize, 0usize, 0usize, 0usize);
    let resm = map.res_mm() as f64 / 1000.0;
    for cy in 0..map.height() as i32 {
        for cx in 0..map.width() as i32 {
            let st = map.state(cx, cy);
            if st == CellState::Unknown {
                continue;
            }
            let (x, y) = (
                (cx as f64 + 0.5) * resm,
                (map.height() as f64 - cy as f64 - 0.5) * resm,
            );
            let truth_occ = world.blocked_at(x, y);
            seen += 1;
            if truth_occ == (st == CellState::Occupied) {
                correct += 1;
            }
            if truth_occ {
                occ_seen += 1;
                false_free += usize::from(st == CellState::Free);
            } else {
                free_seen += 1;
                false_obs += usize::from(st == CellState::Occupied);
            }
        }
    }
    rep.map_cells_seen = seen;
    rep.map_correct_share = correct as f64 / seen.max(1) as f64;
    rep.map_false_obstacle_share = false_obs as f64 / free_seen.max(1) as f64;
    rep.map_false_free_share = false_free as f64 / occ_seen.max(1) as f64;
}

/// Of the cells the body swept (truly free), the share the map calls
/// occupied.
fn path_false_obstacles(
    map: &EvidenceMap<HOST_EVIDENCE>,
    trajectory: &[(f64, f64)],
    r: f64,
) -> f64 {
    let resm = map.res_mm() as f64 / 1000.0;
    let mut swept = std::collections::HashSet::new();
    for &(x, y) in trajectory {
        let rc = (r / resm).ceil() as i32;
        let (cx, cy) = map.cell_of((x * 1000.0) as i32, (y * 1000.0) as i32);
        for dy in -rc..=rc {
            for dx in -rc..=rc {
                let (ccx, ccy) = (
                    (cx + dx) as f64 + 0.5,
                    (map.height() as i32 - 1 - (cy + dy)) as f64 + 0.5,
                );
                if (ccx * resm - x).hypot(ccy * resm - y) <= r - resm * 0.71 {
                    swept.insert((cx + dx, cy + dy));
                }
            }
        }
    }
    let swept_occ = swept
        .iter()
        .filter(|&&(x, y)| map.state(x, y) == CellState::Occupied)
        .count();
    swept_occ as f64 / swept.len().max(1) as f64
}

/// The drive as an SVG: truth in grey, the lidar map over it (occupied
/// red, free pale blue), the true path green, the odometry path dashed.
pub fn drive_svg(
    map: &MapData,
    cell_m: f64,
    t: &DriveTrace,
    rep: &DriveReport,
    title: &str,
) -> String {
    let mut c = Canvas::for_map(map, cell_m, 90.0);
    c.blocked(map, cell_m, "#bbb");
    let res = t.map.res_mm() as f64 / 1000.0;
    let r = res * c.s;
    for cy in 0..t.map.height() as i32 {
        for cx in 0..t.map.width() as i32 {
            let (colour, op) = match t.map.state(cx, cy) {
                CellState::Occupied => ("#d62728", r#" opacity="0.9""#),
                CellState::Free => ("#9ecae1", r#" opacity="0.35""#),
                CellState::Unknown => continue,
            };
            c.rect_px((cx as f64 * r, cy as f64 * r, r, r), colour, op);
        }
    }
    c.polyline(&t.truth, 5, r##"stroke="#2ca02c" stroke-width="2""##);
    c.polyline(
        &t.odom,
        5,
        r##"stroke="#1f3f9f" stroke-width="1.5" stroke-dasharray="6,4""##,
    );
    let lines = [
        title.to_string(),
        format!("odometry error at the end {:.1} mm, {:.1} mrad (max {:.1} mm) over {:.1} m in {:.0} s; collisions {}", rep.final_position_error_mm, rep.final_heading_error_mrad, rep.max_position_error_mm, rep.distance_m, rep.sim_time_s, rep.collisions),
        format!("map: {} cells seen, {:.2} % classified correctly, false obstacles on the path {:.3} %; frames {} (CRC failures {})", rep.map_cells_seen, 100.0 * rep.map_correct_share, 100.0 * rep.path_false_obstacle_rate, rep.parser.frames, rep.parser.crc_failures),
        "grey: truth · red: mapped obstacles · blue: mapped free · green: true path · dashed: odometry".to_string(),
    ];
    c.finish(&lines)
}

/// The wheel speed step response from rest to `target_m_s` on open floor:
/// (rise time 10–90 % in s, overshoot as a share, steady-state error as a
/// share of the target), from the true wheel speeds.
pub fn step_response(noise: Noise, target_m_s: f64, seed: u64) -> (f64, f64, f64) {
    let cfg = RobotConfig::default();
    let open = MapData {
        width: 400,
        height: 40,
        blocked: vec![false; 400 * 40],
        cell_m: None,
        ..Default::default()
    };
    let world = World::new(open, 0.1);
    let mut sim = Sim::new(cfg.clone(), world, (1.0, 2.0, 0.0), noise, seed);
    let geom = cfg.geometry();
    let mut wheels = WheelControl::new(cfg.gains, (cfg.wheelbase_m * 1000.0) as i32);
    let mut last = [sim.encoder(0), sim.encoder(1)];
    let mut prev = [0i32; 2];
    let mut samples = Vec::new();
    for _ in 0..300 {
        for _ in 0..(cfg.control_period_us / cfg.physics_step_us) {
            sim.step();
        }
        let now = [sim.encoder(0), sim.encoder(1)];
        let d = [
            now[0].wrapping_sub(last[0]) as i16 as i32,
            now[1].wrapping_sub(last[1]) as i16 as i32,
        ];
        last = now;
        let meas = [0, 1].map(|i| {
            ((d[i] + prev[i]) as i64 * geom.um_per_tick() * 1000
                / (2 * cfg.control_period_us as i64)) as i32
        });
        prev = d;
        let (dl, dr) = wheels.step(
            (target_m_s * 1000.0) as i32,
            0,
            meas[0],
            meas[1],
            d[0] != 0,
            d[1] != 0,
            cfg.control_period_us as u32,
        );
        sim.set_duty(dl, dr);
        let v = sim.wheel_speeds();
        samples.push(0.5 * (v[0] + v[1]));
    }
    let dt = cfg.control_period_us as f64 * 1e-6;
    let t10 = samples
        .iter()
        .position(|&v| v >= 0.1 * target_m_s)
        .unwrap_or(0) as f64
        * dt;
    let t90 = samples
        .iter()
        .position(|&v| v >= 0.9 * target_m_s)
        .unwrap_or(samples.len()) as f64
        * dt;
    let peak = samples.iter().cloned().fold(0.0, f64::max);
    let tail = &samples[samples.len() - 50..];
    let ss = tail.iter().sum::<f64>() / tail.len() as f64;
    (
        t90 - t10,
        ((peak - target_m_s) / target_m_s).max(0.0),
        (ss - target_m_s).abs() / target_m_s,
    )
}
