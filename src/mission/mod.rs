//! The mission executive: the state machine that runs a whole cleaning
//! mission from the robot's sensors to its motors, driven by a tick with
//! the time passed in (seed 001 and seed 002's closed loop, ALGORITHMS.md
//! §3; the states are the issue's).
//!
//! ```text
//! SelfTest ─► Cover ⇄ Transit ─► Edge ─► Return ─► Done
//!               │ ▲  (Avoid, BackOff: from any driving state, and back)
//!               ▼ │
//!   faults: LidarSilent (motors stopped, resumes), Failed(fault)
//! ```
//!
//! - **SelfTest**: two complete lidar revolutions within 3 s, then a short
//!   turn in place that must move both encoders the right way.
//! - **Cover / Transit**: the coverage planner ([`crate::coverage`]) on
//!   planning cells of `plan_cell_mm`, free where the robot plus margin
//!   fits at the centre ([`crate::nav::cspace`]). Every waypoint's straight
//!   segment is re-checked on the fine map; one that is not clear (a wall's
//!   end between two cell centres) becomes a detour: an A* path on the fine
//!   configuration space.
//! - **Edge**: the edge pass ([`crate::nav::edge`]) along every wall and piece of
//!   furniture, which sweeps the strips the planning cells leave.
//! - **Return**: A* on the fine configuration space to the start (the dock).
//! - **Avoid**: when something the map does not explain lies in the
//!   corridor ahead, DWA ([`crate::nav::dwa`]) steers toward the end of the
//!   current straight sub-path; once the straight line from the robot to
//!   that end is clear, the robot rejoins it. DWA with no admissible motion:
//!   turn in place toward the goal. Given up after `avoid_timeout_us`.
//! - **BackOff**: a wheel stall backs the robot off and retries; after
//!   `stall_retries` the sub-path is dropped and its planning cell marked
//!   blocked.
//! - **LidarSilent**: no valid frame for `lidar_timeout_us` (200 ms): the
//!   motors brake until frames return; after `lidar_lost_us` the mission
//!   fails.
//! - Capacity (map, lists, paths) exceeded: `Failed(Fault::Capacity)`,
//!   never a panic.
//!
//! Under every state the guard ([`crate::nav::guard`]) caps the linear speed
//! from the latest lidar points, so the robot brakes before anything it
//! can see, whatever the plan, the map or the odometry believe.
//!
//! **Map modes.** Known: the caller fills the evidence map with the prior
//! map before [`Mission::begin`]; it is not changed. Unknown: the map
//! starts unknown and every lidar revolution is ray-cast into it; unknown
//! space counts as free for planning (the planner re-plans as walls
//! appear) and as blocked for the edge pass and the way home.
//!
//! **Rates and work bounds.** [`Mission::tick`] runs every control period
//! (100 Hz): odometry, the sub-path follower, the guard over `RING` points,
//! wheel control. Every `plan_period_us` (10 Hz) one planning step runs
//! inside it: at most `node_budget` search nodes (coverage transit, detour,
//! edge transit or the way home), one edge-pass move or fill sweep, one DWA
//! cycle (77 rollouts against 64 points), the corridor check over `RING`
//! points, and in unknown mode one planning-grid update (cells × disc).
//! [`Mission::feed_lidar`] takes bytes as they arrive: the parser per
//! byte, per frame 12 points into the ring, per revolution (unknown mode)
//! one ray-cast update of the map. The largest single steps are one-offs
//! with a grid-sized bound: building the fine configuration space
//! (blocking cells × disc) when the edge pass starts, and one grid scan
//! per edge-pass contour for its next goals.

use crate::coverage::{Coverage, CoverageError, PlannerKind, Step};
use crate::grid::{Cell, Grid, Layer};
use crate::nav::cspace;
use crate::nav::dwa::{self, DwaParams, DwaResult, MAX_OBSTACLES};
use crate::nav::edge::{EdgePass, EdgeStep};
use crate::nav::follow::{follow, FollowCmd, FollowParams, SubPath, SubPaths};
use crate::nav::geometry::{
    dist_mm, explained, in_corridor, nearest_free_fine, nearest_free_fine_within, prune_clear,
    segment_clear, to_robot,
};
use crate::nav::guard::{free_distance_mm, limit_speed, GuardParams};
use crate::robot::lidar::ld06::Ld06;
use crate::robot::lidar::scan::{Scan, ScanAssembler};
use crate::robot::lidar::LidarProtocol;
use crate::robot::lidar_map::{beams, CellState, EvidenceMap, LidarMount};
use crate::robot::odometry::{DriveGeometry, Odometry, Pose};
use crate::robot::wheel_control::{WheelControl, WheelGains};
use crate::search::{Algo, Progress, SearchError, SearchState};
use crate::verify::metrics::SegmentKind;

/// Lidar hit points kept (world mm): a little over one revolution.
pub const RING: usize = 512;
/// Frames per lidar revolution held by the scan assembler.
pub const SCAN_FRAMES: usize = 48;
/// Straight sub-paths queued ahead of the robot.
pub const QUEUE: usize = 48;
/// Grid obstacles near the robot offered to DWA besides the lidar points.
const MAP_POINTS: usize = 64;
/// Plans of the way home tried (one per planning step, 10 Hz) before the
/// mission fails with [`Fault::NoWayHome`]: 30 s for whoever blocks the
/// way to move on.
pub const HOME_TRIES: u16 = 300;
/// Sub-paths given up and put back for a later pass, at most, per mission
/// (a spot a person keeps blocking is not retried for ever).
pub const MAX_RETRIES: u32 = 400;

/// Where the map comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MapMode {
    /// A prior map is given (seed 002's setting).
    Known,
    /// The map starts empty and grows from the lidar (seed 001's setting).
    Unknown,
}

/// Why a mission failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Fault {
    /// No two complete lidar revolutions within the self-test's 3 s.
    SelfTestLidar,
    /// A wheel did not turn in the self-test.
    SelfTestWheels,
    /// The robot does not start in a place it can clean from.
    StartBlocked,
    /// A map, list or path capacity was exceeded.
    Capacity,
    /// The lidar stayed silent past `lidar_lost_us`.
    LidarLost,
    /// No path back to the start.
    NoWayHome,
}

impl Fault {
    /// A short human-readable description.
    pub const fn as_str(self) -> &'static str {
        match self {
            Fault::SelfTestLidar => "self-test: no lidar revolutions",
            Fault::SelfTestWheels => "self-test: a wheel does not turn",
            Fault::StartBlocked => "the start is blocked",
            Fault::Capacity => "map, list or path capacity exceeded",
            Fault::LidarLost => "lidar lost",
            Fault::NoWayHome => "no path back to the start",
        }
    }
}

/// What the executive is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum State {
    /// Checking lidar and wheels.
    SelfTest,
    /// Cleaning lanes.
    Cover,
    /// Driving to the next uncleaned place (backtracking).
    Transit,
    /// Steering around something the map did not have.
    Avoid,
    /// Backing off after a stall.
    BackOff,
    /// Cleaning along walls and furniture.
    Edge,
    /// Driving back to the start.
    Return,
    /// Motors stopped: the lidar is silent.
    LidarSilent,
    /// Mission complete, back at the start.
    Done,
    /// Mission aborted.
    Failed(Fault),
}

/// Motor output for this tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MotorCmd {
    /// Duties, permille.
    Duty(i16, i16),
    /// Brake both motors.
    Brake,
}

/// Everything tunable, units in the names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MissionConfig {
    /// Map mode.
    pub mode: MapMode,
    /// Coverage planner.
    pub kind: PlannerKind,
    /// Wheels and encoders.
    pub geometry: DriveGeometry,
    /// Wheel speed control.
    pub gains: WheelGains,
    /// Body radius, mm.
    pub radius_mm: i32,
    /// Clearance kept from mapped obstacles beyond the radius, mm.
    pub margin_mm: i32,
    /// Planning cell side, mm (about the cleaning width).
    pub plan_cell_mm: u32,
    /// Path follower.
    pub follow: FollowParams,
    /// DWA.
    pub dwa: DwaParams,
    /// Guard.
    pub guard: GuardParams,
    /// The lidar's mounting.
    pub mount: LidarMount,
    /// Lidar silence that stops the motors, µs.
    pub lidar_timeout_us: u64,
    /// Lidar silence that fails the mission, µs.
    pub lidar_lost_us: u64,
    /// Planning period, µs (10 Hz).
    pub plan_period_us: u64,
    /// Search nodes per planning step.
    pub node_budget: u32,
    /// Lateral distance (mm, beyond the radius) at which an unexplained
    /// point in the corridor ahead starts an avoidance.
    pub corridor_mm: i32,
    /// Corridor length checked ahead, mm.
    pub lookahead_mm: i32,
    /// Avoidance given up after, µs.
    pub avoid_timeout_us: u64,
    /// How long an avoidance first waits for the way to clear, µs.
    pub avoid_wait_us: u64,
    /// A sub-path not finished in this long is dropped, µs.
    pub subpath_timeout_us: u64,
    /// Stall retries before a sub-path is dropped.
    pub stall_retries: u8,
    /// Known mode: keep ray-casting the lidar into the prior map, so what
    /// the robot sees (in its own, possibly drifting, frame) is planned
    /// around. Off: the prior map is fixed.
    pub map_known_updates: bool,
    /// Cleaning time before the robot heads home whatever is left (the
    /// battery's share for cleaning), µs.
    pub battery_us: u64,
    /// Closer than this to two lidar points (beyond the radius), the robot
    /// stops turning and backs straight away from them, mm.
    pub escape_mm: i32,
}

impl MissionConfig {
    /// Defaults for a 330 mm robot cleaning at 0.3 m/s with an LD06.
    pub const fn new(
        mode: MapMode,
        geometry: DriveGeometry,
        gains: WheelGains,
        mount: LidarMount,
    ) -> Self {
        let radius_mm = 165;
        let mut dwa = dwa::DEFAULT_PARAMS;
        dwa.radius_mm = radius_mm + 15;
        dwa.v_max_mm_s = 300;
        Self {
            mode,
            kind: PlannerKind::BOha,
            geometry,
            gains,
            radius_mm,
            margin_mm: 10,
            plan_cell_mm: 300,
            // Tighter than the drive defaults: a cleaning run keeps 10 mm
            // from walls, so sub-paths end within 10 mm and the robot turns
            // to within 0.1 rad before it drives.
            follow: FollowParams {
                arrive_mm: 10,
                turn_in_place_mrad: 100,
                min_mm_s: 30,
                ..crate::nav::follow::DEFAULT_FOLLOW
            },
            dwa,
            guard: GuardParams {
                radius_mm: radius_mm + 2,
                brake_mm_s2: 500,
                reserve_mm: 20,
                creep_mm_s: 40,
                moving_margin_mm: 60,
            },
            mount,
            lidar_timeout_us: 200_000,
            lidar_lost_us: 10_000_000,
            plan_period_us: 100_000,
            node_budget: 4000,
            corridor_mm: 5,
            lookahead_mm: 800,
            avoid_timeout_us: 12_000_000,
            avoid_wait_us: 2_000_000,
            subpath_timeout_us: 30_000_000,
            stall_retries: 2,
            escape_mm: 0,
            battery_us: 75 * 60 * 1_000_000,
            map_known_updates: true,
        }
    }

    /// Margins for a lidar whose range noise is `noise_mm` (1 σ): the
    /// clearance kept from mapped walls grows by 2 σ and the guard's
    /// corridor by 1.5 σ, so passing a wall does not look like driving
    /// into it and a noisy wall is not grazed. 0 for an ideal sensor.
    pub const fn with_lidar_noise(mut self, noise_mm: i32) -> Self {
        self.margin_mm = 10 + 2 * noise_mm;
        self.guard.radius_mm = self.radius_mm + 2 + noise_mm * 3 / 2;
        self.escape_mm = 2 + noise_mm / 2;
        self.dwa.radius_mm = self.radius_mm + 15 + noise_mm;
        self
    }
}

/// Event counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Counters {
    /// Avoidances started.
    pub avoidance_events: u32,
    /// DWA cycles with no admissible motion.
    pub dwa_no_admissible: u32,
    /// Lidar silences that stopped the motors.
    pub lidar_silences: u32,
    /// Wheel stalls.
    pub stalls: u32,
    /// Planning cells marked blocked after repeated stalls.
    pub blocked_cells: u32,
    /// Sub-paths given up (timeouts, avoidance timeouts, stalls).
    pub skipped: u32,
    /// Waypoint segments re-routed on the fine map.
    pub detours: u32,
    /// Cover or edge sub-paths given up and put back for a later pass.
    pub retried: u32,
    /// Legs re-planned from where the robot stood after the guard held it
    /// (a wall the plan did not know of, or odometry drift).
    pub replans: u32,
    /// Missions cut short by the battery budget.
    pub battery_returns: u32,
    /// Times the planner's given-up goals were tried again.
    pub abandoned_retries: u32,
    /// Control ticks spent backing away from something at touching
    /// distance.
    pub escapes: u32,
    /// Control ticks on which the guard lowered the speed.
    pub guard_ticks: u32,
    /// Lidar revolutions.
    pub scans: u32,
    /// Planning steps run.
    pub plan_steps: u32,
}

/// The big buffers the executive works in, owned by the caller (statics
/// on the robot, heap boxes on the host).
pub struct Parts<
    'a,
    const N: usize,
    const NW: usize,
    const OPEN: usize,
    const LCAP: usize,
    const PCAP: usize,
    const EV: usize,
> {
    /// The coverage planner.
    pub planner: &'a mut Coverage<N, NW, OPEN, LCAP, PCAP>,
    /// The fine-grid searches' state (detours, edge transits, the way
    /// home), separate from the planner's so neither clobbers the other.
    pub search: &'a mut SearchState<N, NW, OPEN>,
    /// Planning cells.
    pub coarse: &'a mut Grid<NW>,
    /// The fine configuration space (the evidence map's cells).
    pub fine: &'a mut Grid<NW>,
    /// The evidence map (known mode: filled with the prior map).
    pub map: &'a mut EvidenceMap<EV>,
    /// Fine path buffer (detours, edge transits, the way home).
    pub path: &'a mut [Cell],
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Idle,
    SelfTestScan { since_us: u64 },
    SelfTestWheels { until_us: u64, enc0: (u16, u16) },
    SelfTestSettle { until_us: u64 },
    Cover,
    Edge,
    ReturnSearch,
    Return,
    Done,
    Failed(Fault),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Activity {
    Follow,
    Avoid,
    BackOff { until_us: u64 },
}

/// A fine-grid path being fed into the queue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Feed {
    searching: bool,
    len: usize,
    pos: usize,
    cover: bool,
    /// The exact end point to queue after the path's cells.
    then: Option<(i32, i32)>,
}

/// The executive's own state (small; the big buffers are in [`Parts`]).
pub struct Mission {
    cfg: MissionConfig,
    odom: Odometry,
    wheels: WheelControl,
    parser: Ld06,
    asm: ScanAssembler<SCAN_FRAMES>,
    scan: Scan<SCAN_FRAMES>,
    /// Lidar hits, world mm, and whether the map explains each.
    ring: [(i32, i32, bool); RING],
    ring_len: usize,
    ring_head: usize,
    queue: SubPaths<QUEUE>,
    phase: Phase,
    activity: Activity,
    halted_since: Option<u64>,
    last_tick_us: Option<u64>,
    last_frame_us: u64,
    enc_last: (u16, u16),
    prev_delta: [i32; 2],
    prev_dt_us: u64,
    plan_due_us: u64,
    cmd: (i32, i32),
    dwa_cmd: (i32, i32),
    avoid_since_us: u64,
    subpath_since_us: u64,
    retries: u8,
    start: Pose,
    edge: EdgePass,
    planner_done: bool,
    feed: Option<Feed>,
    map_dirty: bool,
    fine_stale: bool,
    fine_is_edge: bool,
    guard_block_since: Option<u64>,
    replan_target: Option<(i32, i32)>,
    replan_count: u8,
    reopens: u32,
    edge_reopens: u32,
    abandon_rounds: u8,
    home_tries: u16,
    edge_tries: u16,
    started_us: u64,
    counters: Counters,
}

struct Exec<
    'm,
    'p,
    'a,
    const N: usize,
    const NW: usize,
    const OPEN: usize,
    const LCAP: usize,
    const PCAP: usize,
    const EV: usize,
> {
    m: &'m mut Mission,
    p: &'p mut Parts<'a, N, NW, OPEN, LCAP, PCAP, EV>,
}

impl Mission {
    /// A mission waiting for [`Mission::begin`].
    pub const fn new(cfg: MissionConfig) -> Self {
        Self {
            cfg,
            odom: Odometry::new(cfg.geometry),
            wheels: WheelControl::new(cfg.gains, (cfg.geometry.wheelbase_um / 1000) as i32),
            parser: Ld06::new(),
            asm: ScanAssembler::new(),
            scan: Scan::new(),
            ring: [(0, 0, false); RING],
            ring_len: 0,
            ring_head: 0,
            queue: SubPaths::new(),
            phase: Phase::Idle,
            activity: Activity::Follow,
            halted_since: None,
            last_tick_us: None,
            last_frame_us: 0,
            enc_last: (0, 0),
            prev_delta: [0; 2],
            prev_dt_us: 0,
            plan_due_us: 0,
            cmd: (0, 0),
            dwa_cmd: (0, 0),
            avoid_since_us: 0,
            subpath_since_us: 0,
            retries: 0,
            start: Pose {
                x_mm: 0,
                y_mm: 0,
                theta_mrad: 0,
            },
            edge: EdgePass::new(),
            planner_done: false,
            feed: None,
            map_dirty: false,
            fine_stale: true,
            fine_is_edge: false,
            guard_block_since: None,
            replan_target: None,
            replan_count: 0,
            reopens: 0,
            edge_reopens: 0,
            abandon_rounds: 0,
            home_tries: 0,
            edge_tries: 0,
            started_us: 0,
            counters: Counters {
                replans: 0,
                retried: 0,
                escapes: 0,
                abandoned_retries: 0,
                battery_returns: 0,
                avoidance_events: 0,
                dwa_no_admissible: 0,
                lidar_silences: 0,
                stalls: 0,
                blocked_cells: 0,
                skipped: 0,
                detours: 0,
                guard_ticks: 0,
                scans: 0,
                plan_steps: 0,
            },
        }
    }

    /// The configuration.
    pub fn config(&self) -> &MissionConfig {
        &self.cfg
    }

    /// The odometry pose.
    pub fn pose(&self) -> Pose {
        self.odom.pose()
    }

    /// For diagnosis: unmapped lidar points in the corridor ahead of the
    /// current sub-path, and how far the guard would let the robot drive
    /// toward its end (mm).
    pub fn corridor_status(&self) -> (usize, i64) {
        let Some((seg, _)) = self.queue.front() else {
            return (0, 0);
        };
        let pose = self.odom.pose();
        let here = (pose.x_mm, pose.y_mm);
        let (reach, _, ahead) = self.corridor(here, seg.to);
        let n = self
            .points_where(false)
            .filter(|&q| in_corridor(here, ahead, q, reach))
            .count();
        (n, self.free_toward(here, seg.to))
    }

    /// For diagnosis: the lidar points within `r_mm` of the robot (world
    /// mm, mapped or not).
    pub fn points_near(&self, r_mm: i64) -> impl Iterator<Item = (i32, i32, bool)> + '_ {
        let pose = self.odom.pose();
        self.ring
            .iter()
            .take(self.ring_len)
            .copied()
            .filter(move |&(x, y, _)| {
                let (dx, dy) = ((x - pose.x_mm) as i64, (y - pose.y_mm) as i64);
                dx * dx + dy * dy < r_mm * r_mm
            })
    }

    /// The last DWA command (v mm/s, ω mrad/s) while avoiding.
    pub fn dwa_command(&self) -> (i32, i32) {
        self.dwa_cmd
    }

    /// The straight sub-path being driven and whether it cleans.
    pub fn current_subpath(&self) -> Option<(SubPath, bool)> {
        self.queue.front()
    }

    /// Event counters.
    pub fn counters(&self) -> Counters {
        self.counters
    }

    /// The lidar parser's counters.
    pub fn parser_stats(&self) -> crate::robot::lidar::ParserStats {
        self.parser.stats()
    }

    /// The edge pass's counters.
    pub fn edge_stats(&self) -> crate::nav::edge::EdgeStats {
        self.edge.stats
    }

    /// What the executive is doing.
    pub fn state(&self) -> State {
        match self.phase {
            Phase::Failed(f) => State::Failed(f),
            Phase::Done => State::Done,
            Phase::Idle
            | Phase::SelfTestScan { .. }
            | Phase::SelfTestWheels { .. }
            | Phase::SelfTestSettle { .. } => State::SelfTest,
            _ if self.halted_since.is_some() => State::LidarSilent,
            _ => match self.activity {
                Activity::Avoid => State::Avoid,
                Activity::BackOff { .. } => State::BackOff,
                Activity::Follow => match self.phase {
                    Phase::Cover => match self.queue.front() {
                        Some((_, false)) => State::Transit,
                        _ => State::Cover,
                    },
                    Phase::Edge => State::Edge,
                    _ => State::Return,
                },
            },
        }
    }

    /// True once the mission is over (done or failed).
    pub fn finished(&self) -> bool {
        matches!(self.phase, Phase::Done | Phase::Failed(_))
    }

    /// Starts a mission at `start` (world mm, mrad: the dock's place on
    /// the map). Known mode: `parts.map` already holds the prior map.
    /// Unknown mode: the caller has sized `parts.map` (all unknown).
    pub fn begin<
        const N: usize,
        const NW: usize,
        const OPEN: usize,
        const LCAP: usize,
        const PCAP: usize,
        const EV: usize,
    >(
        &mut self,
        parts: &mut Parts<'_, N, NW, OPEN, LCAP, PCAP, EV>,
        start: Pose,
    ) {
        let cfg = self.cfg;
        *self = Self::new(cfg);
        self.odom.set_pose(start.x_mm, start.y_mm, start.theta_mrad);
        self.start = start;
        parts.planner.set_kind(cfg.kind);
        let ok = cspace::size_coarse(parts.map, parts.coarse, cfg.plan_cell_mm).is_ok()
            && cspace::update_coarse(
                parts.map,
                parts.coarse,
                cfg.plan_cell_mm,
                (cfg.radius_mm + cfg.margin_mm) as u32,
                false,
            )
            .is_ok();
        self.phase = if ok {
            Phase::SelfTestScan { since_us: 0 }
        } else {
            Phase::Failed(Fault::Capacity)
        };
    }

    /// Feeds lidar bytes as they arrive (`now_us` their arrival time).
    pub fn feed_lidar<
        const N: usize,
        const NW: usize,
        const OPEN: usize,
        const LCAP: usize,
        const PCAP: usize,
        const EV: usize,
    >(
        &mut self,
        parts: &mut Parts<'_, N, NW, OPEN, LCAP, PCAP, EV>,
        bytes: &[u8],
        now_us: u64,
    ) {
        let pose = self.odom.pose();
        for &b in bytes {
            let Some(frame) = self.parser.feed(b) else {
                continue;
            };
            self.last_frame_us = now_us;
            let (ring, head, len) = (&mut self.ring, &mut self.ring_head, &mut self.ring_len);
            let map = &*parts.map;
            beams(&pose, &self.cfg.mount, &frame, 0, |_, _, hx, hy, hit| {
                if hit {
                    if let Some(slot) = ring.get_mut(*head) {
                        *slot = (hx, hy, explained(map, (hx, hy)));
                    }
                    *head = (*head + 1) % RING;
                    *len = (*len + 1).min(RING);
                }
            });
            if self.asm.push(&frame, pose, &mut self.scan) {
                self.counters.scans += 1;
                if self.cfg.mode == MapMode::Unknown || self.cfg.map_known_updates {
                    parts.map.integrate_scan(&self.scan, &self.cfg.mount);
                    self.map_dirty = true;
                    self.fine_stale = true;
                }
            }
        }
    }

    /// One control period: reads the encoders' raw counts, returns the
    /// motor command.
    pub fn tick<
        const N: usize,
        const NW: usize,
        const OPEN: usize,
        const LCAP: usize,
        const PCAP: usize,
        const EV: usize,
    >(
        &mut self,
        parts: &mut Parts<'_, N, NW, OPEN, LCAP, PCAP, EV>,
        now_us: u64,
        enc: (u16, u16),
    ) -> MotorCmd {
        Exec { m: self, p: parts }.tick(now_us, enc)
    }

    /// The corridor checked ahead of the robot toward `to`: its half-width
    /// (mm), the distance to `to` (mm), and where it ends (at most
    /// `lookahead_mm` on).
    fn corridor(&self, here: (i32, i32), to: (i32, i32)) -> (i64, i64, (i32, i32)) {
        let reach = (self.cfg.radius_mm + self.cfg.corridor_mm) as i64;
        let total = dist_mm(here, to);
        let look = self.cfg.lookahead_mm as i64;
        let ahead = if total > look && total > 0 {
            (
                here.0 + ((to.0 - here.0) as i64 * look / total) as i32,
                here.1 + ((to.1 - here.1) as i64 * look / total) as i32,
            )
        } else {
            to
        };
        (reach, total, ahead)
    }

    /// How far the guard would let the robot drive from `here` straight
    /// toward `target` (after its reserves), mm.
    fn free_toward(&self, here: (i32, i32), target: (i32, i32)) -> i64 {
        let toward =
            crate::math::angle::atan2_urad((target.1 - here.1) as i64, (target.0 - here.0) as i64);
        let facing = Pose {
            x_mm: here.0,
            y_mm: here.1,
            theta_mrad: (toward / 1000) as i32,
        };
        let g = self.cfg.guard;
        let fs = free_distance_mm(
            self.points_where(true).map(|q| to_robot(&facing, q)),
            g.radius_mm,
            true,
        ) as i64
            - g.reserve_mm as i64;
        let fm = free_distance_mm(
            self.points_where(false).map(|q| to_robot(&facing, q)),
            g.radius_mm + g.moving_margin_mm,
            true,
        ) as i64
            - (g.reserve_mm + g.moving_margin_mm) as i64;
        fs.min(fm)
    }

    /// The latest lidar hits, world mm.
    fn points(&self) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.ring
            .iter()
            .take(self.ring_len)
            .map(|&(x, y, _)| (x, y))
    }

    /// The latest lidar hits the map explains (walls, furniture) or not
    /// (people, a moved chair, an unmapped wall).
    fn points_where(&self, mapped: bool) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.ring
            .iter()
            .take(self.ring_len)
            .filter(move |p| p.2 == mapped)
            .map(|&(x, y, _)| (x, y))
    }
}

impl<
        const N: usize,
        const NW: usize,
        const OPEN: usize,
        const LCAP: usize,
        const PCAP: usize,
        const EV: usize,
    > Exec<'_, '_, '_, N, NW, OPEN, LCAP, PCAP, EV>
{
    fn tick(&mut self, now_us: u64, enc: (u16, u16)) -> MotorCmd {
        let m = &mut *self.m;
        let pose = m.odom.update(enc.0, enc.1);
        let Some(last) = m.last_tick_us.replace(now_us) else {
            m.enc_last = enc;
            m.plan_due_us = now_us;
            m.last_frame_us = now_us;
            if let Phase::SelfTestScan { since_us } = &mut m.phase {
                *since_us = now_us;
            }
            m.started_us = now_us;
            return MotorCmd::Brake;
        };
        let dt_us = now_us.saturating_sub(last).max(1);
        let d = [
            enc.0.wrapping_sub(m.enc_last.0) as i16 as i32,
            enc.1.wrapping_sub(m.enc_last.1) as i16 as i32,
        ];
        m.enc_last = enc;
        // Speed over the last two periods, mm/s.
        let span = (dt_us + m.prev_dt_us).max(1) as i64;
        let upt = m.cfg.geometry.um_per_tick();
        let meas = [0usize, 1].map(|i| {
            let p = m.prev_delta.get(i).copied().unwrap_or(0);
            let di = d.get(i).copied().unwrap_or(0);
            ((di + p) as i64 * upt * 1000 / span) as i32
        });
        m.prev_delta = d;
        m.prev_dt_us = dt_us;
        if matches!(m.phase, Phase::Done | Phase::Failed(_) | Phase::Idle) {
            m.cmd = (0, 0);
            return MotorCmd::Brake;
        }
        // Lidar silence (after the self-test's own wait).
        let past_selftest = !matches!(m.phase, Phase::SelfTestScan { .. });
        if past_selftest && now_us.saturating_sub(m.last_frame_us) > m.cfg.lidar_timeout_us {
            let since = *m.halted_since.get_or_insert_with(|| {
                m.counters.lidar_silences += 1;
                now_us
            });
            if now_us.saturating_sub(since) > m.cfg.lidar_lost_us {
                m.phase = Phase::Failed(Fault::LidarLost);
            }
            m.cmd = (0, 0);
            m.wheels.clear_fault();
            return MotorCmd::Brake;
        }
        if m.halted_since.take().is_some() {
            m.subpath_since_us = now_us;
        }
        if m.phase == Phase::Cover {
            let (gx, gy) = cspace::coarse_of(self.p.map, m.cfg.plan_cell_mm, pose.x_mm, pose.y_mm);
            let _ = self.p.coarse.set(Layer::Known, gx, gy, true);
        }
        if now_us >= m.plan_due_us {
            m.plan_due_us = now_us + m.cfg.plan_period_us;
            m.counters.plan_steps += 1;
            self.plan(now_us, &pose);
        }
        let (mut v, mut w) = self.motion(now_us, &pose);
        let m2 = &mut *self.m;
        // Escape: touching distance to something (a person stepped in, or
        // the pose drifted onto a corner). A turn with unequal motors would
        // edge the body into it, so back straight away from it instead.
        let close = (m2.cfg.radius_mm + m2.cfg.escape_mm) as i64;
        let (mut n_close, mut sum_x) = (0i64, 0i64);
        for q in m2.points() {
            let (x, y) = to_robot(&pose, q);
            if (x as i64).pow(2) + (y as i64).pow(2) < close * close {
                n_close += 1;
                sum_x += x as i64;
            }
        }
        if n_close >= 2 && !matches!(m2.phase, Phase::SelfTestWheels { .. }) {
            m2.counters.escapes += 1;
            w = 0;
            v = if sum_x > 0 { -60 } else { 60 };
        }
        // The guard: mapped things with the normal reserve; unmapped ones
        // (which may be people walking) with a wider corridor and a reserve
        // for how far they move while the lidar comes round again.
        if v != 0 {
            let g = m2.cfg.guard;
            // A turning robot is checked along its present heading and the
            // one it will have in a quarter second (the arc's chord).
            let turned = Pose {
                theta_mrad: pose.theta_mrad + w / 4,
                ..pose
            };
            let free_along = |mapped: bool, radius: i32| {
                [pose, turned]
                    .iter()
                    .map(|p| {
                        free_distance_mm(
                            m2.points_where(mapped).map(|q| to_robot(p, q)),
                            radius,
                            v > 0,
                        )
                    })
                    .min()
                    .unwrap_or(i32::MAX)
            };
            let free_static = free_along(true, g.radius_mm);
            let free_moving = free_along(false, g.radius_mm + g.moving_margin_mm);
            let lim_static = limit_speed(&g, v, free_static);
            let moving = GuardParams {
                reserve_mm: g.reserve_mm + g.moving_margin_mm,
                ..g
            };
            let lim_moving = limit_speed(&moving, v, free_moving);
            let lim = if v > 0 {
                lim_static.min(lim_moving)
            } else {
                lim_static.max(lim_moving)
            };
            if lim != v {
                m2.counters.guard_ticks += 1;
            }
            if v > 0 && lim == 0 && m2.activity == Activity::Follow {
                m2.guard_block_since.get_or_insert(now_us);
            } else {
                m2.guard_block_since = None;
            }
            v = lim;
        }
        let m = &mut *self.m;
        let (dl, dr) = m
            .wheels
            .step(v, w, meas[0], meas[1], d[0] != 0, d[1] != 0, dt_us as u32);
        if m.wheels.fault().is_some() {
            m.wheels.clear_fault();
            m.counters.stalls += 1;
            // Something the lidar sees against the body (a person, a chair)
            // is an obstruction to back away from; only a stall with
            // nothing in sight (a rug's edge, a cable) counts toward giving
            // the place up.
            let reach = (m.cfg.radius_mm + 60) as i64;
            let touching = m.points().any(|q| {
                let (dx, dy) = ((q.0 - pose.x_mm) as i64, (q.1 - pose.y_mm) as i64);
                dx * dx + dy * dy < reach * reach
            });
            if !touching {
                m.retries = m.retries.saturating_add(1);
            }
            m.activity = Activity::BackOff {
                until_us: now_us + 1_200_000,
            };
            m.cmd = (0, 0);
            return MotorCmd::Brake;
        }
        m.cmd = (v, w);
        MotorCmd::Duty(dl, dr)
    }

    /// The velocity wanted now, before the guard.
    fn motion(&mut self, now_us: u64, pose: &Pose) -> (i32, i32) {
        let m = &mut *self.m;
        match m.phase {
            Phase::SelfTestWheels { .. } => return (0, 800),
            Phase::Cover | Phase::Edge | Phase::ReturnSearch | Phase::Return => {}
            _ => return (0, 0),
        }
        match m.activity {
            Activity::BackOff { until_us } => {
                if now_us < until_us {
                    return (-100, 0);
                }
                m.activity = Activity::Follow;
                if m.retries > m.cfg.stall_retries {
                    self.skip_front(now_us, true);
                }
                (0, 0)
            }
            Activity::Avoid => m.dwa_cmd,
            Activity::Follow => {
                let Some((seg, _)) = m.queue.front() else {
                    m.subpath_since_us = now_us;
                    return (0, 0);
                };
                if now_us.saturating_sub(m.subpath_since_us) > m.cfg.subpath_timeout_us {
                    self.skip_front(now_us, false);
                    return (0, 0);
                }
                match follow(&m.cfg.follow, &seg, pose) {
                    FollowCmd::Arrived => {
                        m.queue.pop();
                        m.subpath_since_us = now_us;
                        m.retries = 0;
                        (0, 0)
                    }
                    FollowCmd::Drive { v_mm_s, w_mrad_s } => (v_mm_s, w_mrad_s),
                }
            }
        }
    }

    /// Gives up the current sub-path; after repeated stalls its planning
    /// cell is marked blocked.
    fn skip_front(&mut self, now_us: u64, stalled: bool) {
        if let Some((seg, cover)) = self.m.queue.front() {
            if !stalled {
                self.give_up(seg, cover);
            }
        }
        let m = &mut *self.m;
        if let Some((seg, _)) = m.queue.front() {
            if stalled && m.phase == Phase::Cover {
                let (gx, gy) =
                    cspace::coarse_of(self.p.map, m.cfg.plan_cell_mm, seg.to.0, seg.to.1);
                if self.p.coarse.set_obstacle(gx, gy, true).is_ok() {
                    m.counters.blocked_cells += 1;
                }
            }
        }
        m.queue.pop();
        m.counters.skipped += 1;
        m.subpath_since_us = now_us;
        m.retries = 0;
        m.activity = Activity::Follow;
    }

    fn fail(&mut self, f: Fault) {
        self.m.phase = Phase::Failed(f);
        self.m.activity = Activity::Follow;
    }

    /// One planning step (10 Hz).
    fn plan(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        let driving = matches!(
            m.phase,
            Phase::Cover | Phase::Edge | Phase::ReturnSearch | Phase::Return
        );
        // Battery: after the cleaning budget, go home.
        if matches!(m.phase, Phase::Cover | Phase::Edge)
            && now_us.saturating_sub(m.started_us) > m.cfg.battery_us
        {
            m.counters.battery_returns += 1;
            m.feed = None;
            m.activity = Activity::Follow;
            m.queue.reset((pose.x_mm, pose.y_mm));
            m.fine_is_edge = false;
            self.begin_return(pose);
            return;
        }
        let m = &mut *self.m;
        if driving
            && m.activity == Activity::Follow
            && m.guard_block_since
                .is_some_and(|t| now_us.saturating_sub(t) > 1_000_000)
        {
            // Held by the guard. If the map says the way on is clear, what
            // blocks it is not on the map (or the pose drifted): steer
            // around it on the lidar alone (DWA). If the map has learnt of
            // a wall across it: plan the leg again.
            m.guard_block_since = None;
            let here = (pose.x_mm, pose.y_mm);
            let r = (m.cfg.radius_mm + m.cfg.margin_mm / 2) as i64;
            match m.queue.front() {
                Some((_, _)) if segment_clear(self.p.map, here, seg_to(&m.queue), r) => {
                    m.activity = Activity::Avoid;
                    m.avoid_since_us = now_us;
                    m.counters.avoidance_events += 1;
                    m.dwa_cmd = (0, 0);
                }
                _ => self.replan_leg(now_us, pose),
            }
        }
        let m = &mut *self.m;
        match m.phase {
            Phase::SelfTestScan { since_us } => {
                if m.counters.scans >= 2 {
                    m.phase = Phase::SelfTestWheels {
                        until_us: now_us + 400_000,
                        enc0: m.enc_last,
                    };
                } else if now_us.saturating_sub(since_us) > 3_000_000 {
                    self.fail(Fault::SelfTestLidar);
                }
            }
            Phase::SelfTestWheels { until_us, enc0 } => {
                if now_us >= until_us {
                    let dl = m.enc_last.0.wrapping_sub(enc0.0) as i16;
                    let dr = m.enc_last.1.wrapping_sub(enc0.1) as i16;
                    // Turning left: the left wheel backward, the right forward.
                    m.phase = if dl <= -20 && dr >= 20 {
                        Phase::SelfTestSettle {
                            until_us: now_us + 300_000,
                        }
                    } else {
                        Phase::Failed(Fault::SelfTestWheels)
                    };
                }
            }
            Phase::SelfTestSettle { until_us } => {
                if now_us >= until_us {
                    self.start_cover(now_us, pose);
                }
            }
            Phase::Cover => {
                self.refresh_coarse();
                self.watch_corridor(now_us, pose);
                if !self.feed_path() {
                    return;
                }
                self.top_up_cover();
                let m = &mut *self.m;
                if m.planner_done && m.queue.is_empty() && m.feed.is_none() {
                    self.start_edge(pose);
                }
            }
            Phase::Edge => {
                self.watch_corridor(now_us, pose);
                if self.feed_path() {
                    self.top_up_edge();
                }
            }
            Phase::ReturnSearch | Phase::Return => {
                self.watch_corridor(now_us, pose);
                let done = self.feed_path();
                let m = &mut *self.m;
                if done {
                    if m.phase == Phase::ReturnSearch {
                        m.phase = Phase::Return;
                    }
                    if m.queue.is_empty() {
                        // Home only when there: a way home given up on the
                        // way (a timeout) is planned again, a few times.
                        let home = (m.start.x_mm, m.start.y_mm);
                        if dist_mm((pose.x_mm, pose.y_mm), home) <= 100 {
                            m.phase = Phase::Done;
                        } else if m.home_tries < HOME_TRIES {
                            m.home_tries += 1;
                            m.queue.reset((pose.x_mm, pose.y_mm));
                            m.fine_is_edge = false;
                            self.begin_return(pose);
                        } else {
                            self.fail(Fault::NoWayHome);
                        }
                    }
                }
            }
            Phase::Idle | Phase::Done | Phase::Failed(_) => {}
        }
    }

    /// Unknown mode: the planning cells follow the map (the planner's own
    /// cell stays free so it can always search from it).
    fn refresh_coarse(&mut self) {
        let m = &mut *self.m;
        if !m.map_dirty {
            return;
        }
        m.map_dirty = false;
        let r = (m.cfg.radius_mm + m.cfg.margin_mm) as u32;
        if cspace::update_coarse(self.p.map, self.p.coarse, m.cfg.plan_cell_mm, r, false).is_err() {
            self.fail(Fault::Capacity);
            return;
        }
        let (x, y) = self.p.planner.position().xy();
        let _ = self.p.coarse.set_obstacle(x, y, false);
    }

    fn start_cover(&mut self, now_us: u64, pose: &Pose) {
        self.m.map_dirty = true;
        self.refresh_coarse();
        let m = &mut *self.m;
        let cell = m.cfg.plan_cell_mm;
        let (cx, cy) = cspace::coarse_of(self.p.map, cell, pose.x_mm, pose.y_mm);
        // The planning cell the robot is in, or the nearest free one.
        let mut best: Option<(i64, Cell)> = None;
        for dy in -2..=2 {
            for dx in -2..=2 {
                let (x, y) = (cx + dx, cy + dy);
                if !self.p.coarse.is_free(x, y) {
                    continue;
                }
                let d = dist_mm(self.anchor(x, y), (pose.x_mm, pose.y_mm));
                if best.is_none_or(|(b, _)| d < b) {
                    best = Cell::from_xy(x, y).map(|c| (d, c));
                }
            }
        }
        let Some((_, start)) = best else {
            self.fail(Fault::StartBlocked);
            return;
        };
        if self.p.planner.start(self.p.coarse, start).is_err() {
            self.fail(Fault::StartBlocked);
            return;
        }
        let m = &mut *self.m;
        m.queue.reset((pose.x_mm, pose.y_mm));
        m.phase = Phase::Cover;
        m.subpath_since_us = now_us;
        let to = self.anchor(start.x as i32, start.y as i32);
        self.enqueue(to, true);
    }

    /// World mm where the robot stands for planning cell (x, y).
    fn anchor(&self, x: i32, y: i32) -> (i32, i32) {
        let c = &self.m.cfg;
        let r = (c.radius_mm + c.margin_mm) as u32;
        cspace::anchor_mm(self.p.map, c.plan_cell_mm, r, x, y)
    }

    /// Asks the planner for waypoints until a few are queued.
    fn top_up_cover(&mut self) {
        let budget = self.m.cfg.node_budget;
        while self.m.queue.len() < 4 && !self.m.planner_done && self.m.feed.is_none() {
            match self.p.planner.step(self.p.coarse, budget) {
                Ok(Step::Move(w)) => {
                    let (x, y) = w.to.xy();
                    let to = self.anchor(x, y);
                    self.enqueue(to, w.kind == SegmentKind::Cover);
                }
                Ok(Step::Pending) => break,
                Ok(Step::Done) => {
                    // Goals given up while the map was different (a person
                    // in a doorway) get up to two more chances.
                    let at = self.p.planner.position();
                    if self.m.abandon_rounds < 2 && self.p.planner.retry_abandoned(at) > 0 {
                        self.m.abandon_rounds += 1;
                        self.m.counters.abandoned_retries += 1;
                    } else {
                        self.m.planner_done = true;
                    }
                }
                Err(CoverageError::Search(SearchError::StartBlocked)) => {
                    // The map moved under the planner: free its cell and
                    // try again next step.
                    let (x, y) = self.p.planner.position().xy();
                    let _ = self.p.coarse.set_obstacle(x, y, false);
                    break;
                }
                Err(_) => {
                    self.fail(Fault::Capacity);
                    break;
                }
            }
        }
    }

    /// Queues a straight move to `to`, or a detour on the fine map when the
    /// straight segment is not clear.
    fn enqueue(&mut self, to: (i32, i32), cover: bool) {
        let m = &mut *self.m;
        let from = m.queue.last_end().unwrap_or(to);
        let r = (m.cfg.radius_mm + m.cfg.margin_mm / 2) as i64;
        if segment_clear(self.p.map, from, to, r) {
            if !m.queue.push(to, cover) {
                self.fail(Fault::Capacity);
            }
            return;
        }
        self.detour(from, to, cover);
    }

    /// Queues an A* path on the fine configuration space from `from` to
    /// `to` (the fine grid is rebuilt first when the map changed during
    /// coverage; the edge pass's grid is used as it is).
    fn detour(&mut self, from: (i32, i32), to: (i32, i32), cover: bool) {
        let m = &mut *self.m;
        if m.fine_stale && !m.fine_is_edge {
            let r = (m.cfg.radius_mm + m.cfg.margin_mm) as u32;
            if cspace::build_fine(self.p.map, self.p.fine, r, false).is_err() {
                self.fail(Fault::Capacity);
                return;
            }
            m.fine_stale = false;
        }
        m.edge.interrupt();
        let a = nearest_free_fine(self.p.map, self.p.fine, from);
        let b = nearest_free_fine(self.p.map, self.p.fine, to);
        let (Some(a), Some(b)) = (a, b) else {
            // Not representable on the fine map: drive straight (the guard
            // still protects).
            let _ = m.queue.push(to, cover);
            return;
        };
        m.counters.detours += 1;
        let search = &mut *self.p.search;
        if search.begin(self.p.fine, a, &[b], Algo::AStar).is_err() {
            let _ = m.queue.push(to, cover);
            return;
        }
        m.feed = Some(Feed {
            searching: true,
            len: 0,
            pos: 0,
            cover,
            then: Some(to),
        });
    }

    /// Advances the fine path being fed (search, then queueing its cells).
    /// True when nothing is left to feed.
    fn feed_path(&mut self) -> bool {
        let Some(mut f) = self.m.feed else {
            return true;
        };
        if f.searching {
            let search = &mut *self.p.search;
            match search.resume(self.p.fine, self.m.cfg.node_budget) {
                Ok(Progress::Pending { .. }) => return false,
                Ok(Progress::Found(_)) => match search.write_path(self.p.path) {
                    Ok(n) => {
                        let r = (self.m.cfg.radius_mm + self.m.cfg.margin_mm / 2) as i64;
                        f.len =
                            prune_clear(self.p.map, self.p.path.get_mut(..n).unwrap_or(&mut []), r);
                        f.searching = false;
                    }
                    Err(_) => {
                        self.fail(Fault::Capacity);
                        return false;
                    }
                },
                Err(SearchError::NoPath) => {
                    self.m.feed = None;
                    if self.m.phase == Phase::ReturnSearch {
                        // No way home on this map: plan again from a fresh
                        // map (the Return phase counts the tries).
                        self.m.phase = Phase::Return;
                        self.m.fine_is_edge = false;
                    } else {
                        self.m.counters.skipped += 1;
                    }
                    return true;
                }
                Err(_) => {
                    self.fail(Fault::Capacity);
                    return false;
                }
            }
        }
        let m = &mut *self.m;
        while f.pos < f.len && m.queue.len() + 1 < QUEUE {
            let Some(&c) = self.p.path.get(f.pos) else {
                break;
            };
            let p = cspace::fine_centre_mm(self.p.map, c.x as i32, c.y as i32);
            if !m.queue.push(p, f.cover) {
                break;
            }
            f.pos += 1;
        }
        if f.pos < f.len {
            m.feed = Some(f);
            return false;
        }
        if let Some(t) = f.then {
            if m.queue.len() + 1 >= QUEUE || !m.queue.push(t, f.cover) {
                m.feed = Some(f);
                return false;
            }
        }
        m.feed = None;
        true
    }

    fn start_edge(&mut self, pose: &Pose) {
        let m = &mut *self.m;
        let r = (m.cfg.radius_mm + m.cfg.margin_mm) as u32;
        let unknown_blocks = m.cfg.mode == MapMode::Unknown;
        if cspace::build_fine(self.p.map, self.p.fine, r, unknown_blocks).is_err() {
            self.fail(Fault::Capacity);
            return;
        }
        m.fine_is_edge = true;
        let from = nearest_free_fine_within(self.p.map, self.p.fine, (pose.x_mm, pose.y_mm), 10);
        let Some(from) = from else {
            // Boxed in on the map (someone beside the robot is mapped):
            // try again next step, for up to 30 s, then skip the edge pass.
            m.edge_tries += 1;
            m.fine_is_edge = false;
            if m.edge_tries > HOME_TRIES {
                m.phase = Phase::ReturnSearch;
                self.begin_return(pose);
            }
            return;
        };
        m.queue.reset((pose.x_mm, pose.y_mm));
        let fc = cspace::fine_centre_mm(self.p.map, from.x as i32, from.y as i32);
        let _ = m.queue.push(fc, false);
        if !m.edge.start(self.p.fine, from) {
            m.phase = Phase::ReturnSearch;
            self.begin_return(pose);
            return;
        }
        m.phase = Phase::Edge;
    }

    fn top_up_edge(&mut self) {
        let budget = self.m.cfg.node_budget;
        while self.m.queue.len() < 8 {
            let search = &mut *self.p.search;
            match self.m.edge.step(self.p.fine, search, self.p.path, budget) {
                Ok(EdgeStep::Move { .. } | EdgeStep::Done)
                    if self.m.edge.stats.reached * 2 < self.m.edge.stats.free
                        && self.m.edge_tries < HOME_TRIES =>
                {
                    // Boxed in on the map (someone who stood beside the
                    // robot is still mapped around it): wait and build the
                    // edge pass again from a fresher map.
                    let m = &mut *self.m;
                    m.edge_tries += 1;
                    m.edge = EdgePass::new();
                    m.queue.reset(m.queue.last_end().unwrap_or((0, 0)));
                    m.fine_is_edge = false;
                    m.phase = Phase::Cover;
                    return;
                }
                Ok(EdgeStep::Move { to, edge }) => {
                    let p = cspace::fine_centre_mm(self.p.map, to.x as i32, to.y as i32);
                    let _ = self.m.queue.push(p, edge);
                }
                Ok(EdgeStep::Pending) => return,
                Ok(EdgeStep::Done) => {
                    self.m.phase = Phase::ReturnSearch;
                    let pose = self.m.odom.pose();
                    self.begin_return(&pose);
                    return;
                }
                Err(_) => {
                    self.fail(Fault::Capacity);
                    return;
                }
            }
        }
    }

    /// Plans the way home from the end of the queue to the start.
    fn begin_return(&mut self, pose: &Pose) {
        let m = &mut *self.m;
        m.phase = Phase::ReturnSearch;
        if !m.fine_is_edge {
            let r = (m.cfg.radius_mm + m.cfg.margin_mm) as u32;
            let unknown_blocks = m.cfg.mode == MapMode::Unknown;
            if cspace::build_fine(self.p.map, self.p.fine, r, unknown_blocks).is_err() {
                self.fail(Fault::Capacity);
                return;
            }
        }
        let from = m.queue.last_end().unwrap_or((pose.x_mm, pose.y_mm));
        let home = (m.start.x_mm, m.start.y_mm);
        // Look wider than for a detour: the dock may have been mapped a
        // little off (drift), or someone stands beside the robot.
        let a = nearest_free_fine_within(self.p.map, self.p.fine, from, 10);
        let b = nearest_free_fine_within(self.p.map, self.p.fine, home, 10);
        let (Some(a), Some(b)) = (a, b) else {
            // Try again on the next step (the map changes as people move);
            // the Return phase gives up after `HOME_TRIES`.
            m.phase = Phase::Return;
            m.fine_is_edge = false;
            return;
        };
        if a == b {
            let _ = m.queue.push(home, false);
            m.phase = Phase::Return;
            return;
        }
        let search = &mut *self.p.search;
        if search.begin(self.p.fine, a, &[b], Algo::AStar).is_err() {
            m.phase = Phase::Return;
            m.fine_is_edge = false;
            return;
        }
        m.feed = Some(Feed {
            searching: true,
            len: 0,
            pos: 0,
            cover: false,
            then: Some(home),
        });
    }

    /// A cleaning sub-path the robot could not drive: its cells go back to
    /// the planner (coverage) or the edge pass, to be tried again later in
    /// the phase, up to [`MAX_RETRIES`] per mission.
    fn give_up(&mut self, seg: SubPath, cover: bool) {
        let m = &mut *self.m;
        if !cover || m.reopens >= MAX_RETRIES {
            return;
        }
        if m.phase == Phase::Edge {
            // The edge pass retries at most a tenth as often.
            if m.edge_reopens >= MAX_RETRIES / 10 {
                return;
            }
            m.edge_reopens += 1;
        }
        let len = dist_mm(seg.from, seg.to);
        let mut any = false;
        match m.phase {
            Phase::Cover => {
                let cell = m.cfg.plan_cell_mm;
                let steps = (len / 100).max(1);
                for k in 0..=steps {
                    let x = seg.from.0 as i64 + (seg.to.0 - seg.from.0) as i64 * k / steps;
                    let y = seg.from.1 as i64 + (seg.to.1 - seg.from.1) as i64 * k / steps;
                    let (gx, gy) = cspace::coarse_of(self.p.map, cell, x as i32, y as i32);
                    let g = &mut *self.p.coarse;
                    if g.is_free(gx, gy)
                        && !g.get(Layer::Known, gx, gy)
                        && g.get(Layer::Covered, gx, gy)
                    {
                        let _ = g.set(Layer::Covered, gx, gy, false);
                        if let Some(c) = Cell::from_xy(gx, gy) {
                            self.p.planner.add_point(g, c);
                        }
                        any = true;
                    }
                }
                if any {
                    let at = m.queue.last_end().unwrap_or(seg.to);
                    let (gx, gy) = cspace::coarse_of(self.p.map, cell, at.0, at.1);
                    if let Some(c) = Cell::from_xy(gx, gy)
                        .filter(|c| self.p.coarse.is_free(c.x as i32, c.y as i32))
                    {
                        self.p.planner.reopen(c);
                    }
                    m.planner_done = false;
                }
            }
            Phase::Edge => {
                let steps = (len / 25).max(1);
                for k in 0..=steps {
                    let x = seg.from.0 as i64 + (seg.to.0 - seg.from.0) as i64 * k / steps;
                    let y = seg.from.1 as i64 + (seg.to.1 - seg.from.1) as i64 * k / steps;
                    let (cx, cy) = self.p.map.cell_of(x as i32, y as i32);
                    let g = &mut *self.p.fine;
                    if crate::nav::edge::is_boundary(g, cx, cy) && g.get(Layer::Covered, cx, cy) {
                        let _ = g.set(Layer::Covered, cx, cy, false);
                        any = true;
                    }
                }
                if any {
                    let at = m.edge.position();
                    m.edge.reopen(at);
                }
            }
            _ => {}
        }
        if any {
            m.reopens += 1;
            m.counters.retried += 1;
        }
    }

    /// The guard has held the robot: the leg ahead runs into something the
    /// plan did not know of (a wall first seen now, or the pose drifted).
    /// Drops the queue and plans a fresh fine-map path from where the robot
    /// stands to where the queue ended; the same target given up after
    /// three tries.
    fn replan_leg(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        m.guard_block_since = None;
        let cover = m.queue.front().is_some_and(|(_, c)| c);
        let target = m.feed.and_then(|f| f.then).or(m.queue.last_end());
        let mut dropped = [(
            SubPath {
                from: (0, 0),
                to: (0, 0),
            },
            false,
        ); QUEUE];
        let mut n = 0;
        for (slot, item) in dropped.iter_mut().zip(m.queue.iter()) {
            *slot = item;
            n += 1;
        }
        for &(seg, c) in dropped.iter().take(n) {
            self.give_up(seg, c);
        }
        let m = &mut *self.m;
        m.feed = None;
        let here = (pose.x_mm, pose.y_mm);
        m.queue.reset(here);
        m.subpath_since_us = now_us;
        m.counters.replans += 1;
        let Some(t) = target else {
            return;
        };
        if m.replan_target == Some(t) {
            m.replan_count += 1;
        } else {
            m.replan_target = Some(t);
            m.replan_count = 1;
        }
        if m.replan_count > 3 {
            m.counters.skipped += 1;
            m.replan_count = 0;
            if m.phase == Phase::Return || m.phase == Phase::ReturnSearch {
                self.fail(Fault::NoWayHome);
            }
            return;
        }
        if m.phase == Phase::ReturnSearch || m.phase == Phase::Return {
            m.phase = Phase::ReturnSearch;
        }
        self.detour(here, t, cover);
    }

    /// Starts and ends avoidance; runs DWA while avoiding.
    fn watch_corridor(&mut self, now_us: u64, pose: &Pose) {
        let m = &mut *self.m;
        let Some((seg, _)) = m.queue.front() else {
            m.activity = Activity::Follow;
            return;
        };
        let here = (pose.x_mm, pose.y_mm);
        let (reach, total, ahead) = m.corridor(here, seg.to);
        match m.activity {
            Activity::BackOff { .. } => {}
            Activity::Follow => {
                let unexplained = m
                    .points_where(false)
                    .filter(|&q| in_corridor(here, ahead, q, reach))
                    .take(2)
                    .count();
                if unexplained >= 2 {
                    m.activity = Activity::Avoid;
                    m.avoid_since_us = now_us;
                    m.counters.avoidance_events += 1;
                    m.dwa_cmd = (0, 0);
                }
            }
            Activity::Avoid => {
                if total < 60 {
                    m.queue.pop();
                    m.activity = Activity::Follow;
                    m.subpath_since_us = now_us;
                    return;
                }
                // Rejoin once nothing unmapped lies in the corridor and the
                // guard would let the robot drive 250 mm straight toward the
                // end (the guard's own rule, so it does not hold it again).
                let unexplained = m
                    .points_where(false)
                    .any(|q| in_corridor(here, ahead, q, reach));
                let free = m.free_toward(here, seg.to);
                if !unexplained && free >= 250.min(total) {
                    m.activity = Activity::Follow;
                    m.subpath_since_us = now_us;
                    // Rejoin straight when the map allows it, else by a
                    // fresh path from here.
                    let r = (m.cfg.radius_mm + m.cfg.margin_mm / 2) as i64;
                    if segment_clear(self.p.map, here, seg.to, r) {
                        m.queue.replace_front(SubPath {
                            from: here,
                            to: seg.to,
                        });
                    } else {
                        self.replan_leg(now_us, pose);
                    }
                    return;
                }
                let waited = now_us.saturating_sub(m.avoid_since_us);
                if waited > m.cfg.avoid_timeout_us {
                    m.activity = Activity::Follow;
                    self.replan_leg(now_us, pose);
                    return;
                }
                if waited < m.cfg.avoid_wait_us {
                    // First wait: people usually walk on.
                    m.dwa_cmd = (0, 0);
                    return;
                }
                self.dwa_step(pose, seg.to);
            }
        }
    }

    fn dwa_step(&mut self, pose: &Pose, goal_world: (i32, i32)) {
        let m = &mut *self.m;
        let mut all = [(0i32, 0i32); RING + MAP_POINTS];
        let mut n = 0usize;
        // Unmapped points (maybe people) are moved closer by the guard's
        // extra margin, so DWA keeps the berth the guard will insist on.
        let extra = m.cfg.guard.moving_margin_mm as i64;
        for &(x, y, mapped) in m.ring.iter().take(m.ring_len) {
            let (rx, ry) = to_robot(pose, (x, y));
            let q = if mapped {
                (rx, ry)
            } else {
                let d = crate::math::cost::isqrt_u64(
                    (rx as i64 * rx as i64 + ry as i64 * ry as i64) as u64,
                )
                .max(1) as i64;
                let k = (d - extra).max(0);
                ((rx as i64 * k / d) as i32, (ry as i64 * k / d) as i32)
            };
            if let Some(s) = all.get_mut(n) {
                *s = q;
                n += 1;
            }
        }
        // Nearby grid obstacles (known mode: the prior map's walls).
        let map = &*self.p.map;
        let (cx, cy) = map.cell_of(pose.x_mm, pose.y_mm);
        let k = (600 / map.res_mm().max(1)) as i32;
        'grid: for y in cy - k..=cy + k {
            for x in cx - k..=cx + k {
                if map.state(x, y) == CellState::Occupied {
                    let c = cspace::fine_centre_mm(map, x, y);
                    match all.get_mut(n) {
                        Some(s) if n < RING + MAP_POINTS => {
                            *s = to_robot(pose, c);
                            n += 1;
                        }
                        _ => break 'grid,
                    }
                }
            }
        }
        let mut obs = [(0i32, 0i32); MAX_OBSTACLES];
        let k = dwa::nearest_obstacles(all.get(..n).unwrap_or(&[]), &mut obs);
        let goal = to_robot(pose, goal_world);
        m.dwa_cmd = match dwa::plan(
            &m.cfg.dwa,
            m.cmd.0.max(0),
            m.cmd.1,
            goal,
            obs.get(..k).unwrap_or(&[]),
        ) {
            DwaResult::Command {
                v_mm_s, w_mrad_s, ..
            } => (v_mm_s, w_mrad_s),
            DwaResult::NoAdmissible => {
                m.counters.dwa_no_admissible += 1;
                // Turn in place toward the goal (a disc cannot hit anything
                // turning in place).
                let bearing = crate::math::angle::atan2_mrad(goal.1, goal.0);
                (0, if bearing >= 0 { 500 } else { -500 })
            }
        };
    }
}

fn seg_to<const C: usize>(q: &SubPaths<C>) -> (i32, i32) {
    q.front().map(|(s, _)| s.to).unwrap_or((0, 0))
}
