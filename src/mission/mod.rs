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
//!   battery low in Cover or Edge: Return ─► Docking ─► Charging ─► back
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
//! - **Charging**: the charge ran low while cleaning ([`battery`]): home,
//!   charge on the dock, and back to the lanes or edges where they
//!   stopped.
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
//! appear, and a queued leg the map comes to graze is planned again:
//! [`avoid`]) and as blocked for the edge pass and the way home.
//!
//! **Real-time control and background planning.** The executive has two
//! entry points. [`Mission::control`] runs every control period (100 Hz,
//! at a high interrupt priority on the robot): odometry, the sub-path
//! follower, the guard over `RING` points, wheel control, stall handling;
//! it touches no big buffer, so its cost is bounded and small (one pass
//! over the lidar ring for the escape check, two guard passes, a few
//! integer square roots). [`Mission::plan`] runs every `plan_period_us`
//! (10 Hz, in a low-priority task on the robot) and may take longer: the
//! searches, DWA, map upkeep and the state machine's decisions. They share
//! a small interface: the sub-path queue and the current command (plan
//! writes, control drives them), the latest pose (control writes, plan
//! reads) and the hand-off ([`handoff`]: what control did that the
//! planner's buffers must learn of). [`Mission::tick`] is the host's
//! lock-step: control's sensing half, the planning step when due, then
//! control's acting half, the order every figure was measured in.
//!
//! **Work bounds of a planning step: at most `node_budget` search nodes (coverage transit, detour,
//! edge transit or the way home), one edge-pass move or fill sweep, one DWA
//! cycle (77 rollouts against 64 points), the corridor check over `RING`
//! points, and in unknown mode one planning-grid update (cells × disc).
//! [`Mission::feed_lidar`] (the lidar event) takes bytes as they arrive: the parser per
//! byte, per frame 12 points into the ring, per revolution (unknown mode)
//! one ray-cast update of the map. The largest single steps are one-offs
//! with a grid-sized bound: building the fine configuration space
//! (blocking cells × disc) when the edge pass starts, and one grid scan
//! per edge-pass contour for its next goals.

//!
//! Files: [`config`] and [`events`] are leaves; [`parts`] the caller's
//! buffers; `control` the real-time path; `plan` the state machine's step;
//! `cover`, `edge`, `home`, `recover` and `avoid` its parts; `lidar` the
//! lidar event.

/// An impl for buffers of every size: the header with its nine const
/// generics written once. `sized_impl!([Trait for Type] { items })`, or
/// `sized_impl!([] { items })` for the planning side's methods on
/// [`Exec`] over [`Parts`].
macro_rules! sized_impl {
    ([] $($body:tt)*) => {
        sized_impl!([$crate::mission::Exec<'_, '_, $crate::mission::Parts<'_, N, NW, OPEN, LCAP, PCAP, FW, EV, MW, CF>>] $($body)*);
    };
    ([$($head:tt)*] { $($body:tt)* }) => {
        impl<
                const N: usize,
                const NW: usize,
                const OPEN: usize,
                const LCAP: usize,
                const PCAP: usize,
                const FW: usize,
                const EV: usize,
                const MW: usize,
                const CF: usize,
            > $($head)*
        {
            $($body)*
        }
    };
}

mod avoid;
mod battery;
mod bump;
mod control;
mod cover;
mod edge;
mod handoff;
mod home;
mod inspect;
mod lidar;
mod locate;
pub use locate::STILL_MAP_EVERY;
mod phase;
mod plan;
mod progress;
mod recover;
mod rooms;
mod route;
pub mod scroll;
mod start_check;

pub mod config;
pub mod events;
pub mod parts;
pub mod reflex;

pub use config::{
    Counters, Fault, LocalPlanner, MapMode, MissionConfig, MotorCmd, State, BOXED_NODES,
    BOXED_PLAN_NODES, BOXED_TRIES, BOXED_WAIT_US, EDGE_TRIES, MAX_RETRIES, QUEUE, RETURN_TRIES,
    RING, SCAN_FRAMES, SKIPPED_GOALS,
};
pub use events::{Capacity, Event, EventKind, EVENTS};
pub use handoff::HANDOFF;
pub use parts::{MissionParts, Parts, PlannerView};
pub use reflex::{Reflex, ReflexOut};

use crate::localize::Fusion;
use crate::nav::edge::EdgePass;
use crate::nav::follow::SubPaths;
use crate::nav::geometry::in_corridor;
use crate::nav::keep_off::NearWalls;
pub use crate::robot::hal::Bumper;
use crate::robot::lidar::ld06::Ld06;
use crate::robot::lidar::scan::{Scan, ScanAssembler};
use crate::robot::lidar::LidarProtocol;
use crate::robot::lidar_map::{take_box, union_box, CellBox, NO_CELLS};
use crate::robot::odometry::{Odometry, Pose};
use crate::robot::wheel_control::WheelControl;
use events::Events;
use handoff::Handoff;
use phase::{Activity, Phase};

/// A fine-grid path being fed into the queue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Feed {
    searching: bool,
    len: usize,
    pos: usize,
    cover: bool,
    /// The exact end point to queue after the path's cells.
    then: Option<(i32, i32)>,
    /// Where the path starts, and whether a search that finds no way
    /// inside its window (not the whole map) may take a route over the
    /// whole map in blocks instead ([`route`]; not for a route's own legs).
    from: (i32, i32),
    routable: bool,
}

/// The control path's own state: wheels, encoders and their timing.
struct Drive {
    odom: Odometry,
    wheels: WheelControl,
    last_tick_us: Option<u64>,
    enc_last: (u16, u16),
    prev_delta: [i32; 2],
    prev_dt_us: u64,
    /// The last sensing half ran to the end (not braked early): planning
    /// may run.
    sensed_ok: bool,
    /// The map's height, mm: control finds its planning cell without the
    /// map.
    map_h_mm: i64,
}

/// The lidar side: parser, revolutions, and the ring of recent hits.
struct LidarIn {
    parser: Ld06,
    asm: ScanAssembler<SCAN_FRAMES>,
    scan: Scan<SCAN_FRAMES>,
    /// Lidar hits, world mm, and whether the map explains each.
    ring: lidar::HitRing<RING>,
    last_frame_us: u64,
}

/// The executive's own state (small; the big buffers are in [`Parts`]).
pub struct Mission {
    cfg: MissionConfig,
    drive: Drive,
    lidar: LidarIn,
    // The interface shared by control and planning.
    queue: SubPaths<QUEUE>,
    activity: Activity,
    cmd: (i32, i32),
    dwa_cmd: (i32, i32),
    /// Where the potential field last held the robot in a local minimum,
    /// mm (so that one minimum is counted once, however often the robot,
    /// turning in it, steps in and out of it).
    apf_minimum: Option<(i32, i32)>,
    /// The walls the control loop keeps off, gathered by the planning step.
    near_walls: NearWalls,
    /// When unmapped points were last near the body (µs, 0: never): a
    /// bump soon after is a person's ([`bump::PERSON_RECENT_US`]).
    person_near_us: u64,
    /// The places bumped last and the bumps at each
    /// ([`bump::BumpPlaces`], for [`bump::BELIEVE_AFTER`]).
    bump_places: bump::BumpPlaces,
    handoff: Handoff,
    events: Events,
    phase: Phase,
    // Control's timers.
    halted_since: Option<u64>,
    plan_due_us: u64,
    subpath_since_us: u64,
    retries: u8,
    guard_block_since: Option<u64>,
    /// Since when the robot has not driven (no linear speed commanded;
    /// turning in place counts as standing): [`Mission::start_free`].
    still_since_us: Option<u64>,
    /// Where the move the guard last held (and the leg was planned again
    /// for) led, world mm, and how many times in a row it was held.
    held_to: Option<((i32, i32), u8)>,
    /// The bumper as last read ([`Mission::set_bumper`]).
    bumper: Bumper,
    // Planning's own.
    avoid_since_us: u64,
    start: Pose,
    edge: EdgePass,
    planner_done: bool,
    feed: Option<Feed>,
    /// A long way being fed leg by leg ([`route`]).
    route: route::Route,
    /// The route is feeding a leg (its detours take no route of their own).
    in_route: bool,
    map_dirty: bool,
    /// Someone asked the robot home ([`Mission::request_home`]).
    home_requested: bool,
    /// The planning cells to derive again at the next refresh: around
    /// the map's changed cells, and the cells set by hand since the last
    /// one (the planner's own cell freed, a stalled cell blocked).
    coarse_dirty: CellBox,
    fine_stale: bool,
    fine_is_edge: bool,
    replan_target: Option<(i32, i32)>,
    replan_count: u8,
    reopens: u32,
    edge_reopens: u32,
    /// Where the edge pass gave sub-paths up lately, and how often at
    /// each ([`recover::EDGE_REOPENS_PER_PLACE`]).
    edge_give_ups: bump::BumpPlaces<2>,
    abandon_rounds: u8,
    /// Planning cells of cleaning goals the fine search found no way to.
    skipped_goals: heapless::Vec<crate::grid::Cell, SKIPPED_GOALS>,
    /// A search that found the robot boxed in, to run again once the wait
    /// is over ([`BoxedWait`]), and how many such waits since a detour last
    /// found its way.
    boxed_wait: Option<cover::BoxedWait>,
    boxed_tries: u8,
    /// Cleaning detours that failed in a row from one start.
    pocket: cover::Pocket,
    /// The planner's abandoned-goal count when last seen (a rise means
    /// its last search gave goals up).
    plan_abandoned_seen: u32,
    /// The goals given up were tried once more after the edge pass.
    late_retry: bool,
    /// The cells taken as covered and never driven were handed back once,
    /// after the edge pass: in unknown mode always, in known mode once the
    /// retry budget ran out ([`MAX_RETRIES`]).
    undriven_retry: bool,
    home_tries: u16,
    /// The way home's nearest approach to the dock so far, mm (saturating;
    /// `u16::MAX` before it starts): progress restores the tries.
    home_best_mm: u16,
    edge_tries: u16,
    started_us: u64,
    counters: Counters,
    // Localisation.
    loc: Fusion,
    start_fixed: bool,
    relocated: bool,
    lost_since_us: u64,
    /// A bump was marked: plan the leg again once the back-off ends.
    bump_replan: bool,
    /// The battery: its charge, and the phase to resume after charging.
    battery: battery::Charge,
    /// The planning cells' covered layer holds an earlier run's progress
    /// ([`Mission::restore_progress`]): the lanes plan only the rest.
    restored: bool,
    /// The restored progress has the edge pass's too: the caller restores
    /// it once the edge pass has started ([`Mission::wants_edge_progress`]).
    edge_progress_pending: bool,
    /// The rooms and which are open ([`rooms`]).
    rooms: rooms::RoomTour,
    /// The edge pass's contour gathered into chords.
    chord: crate::nav::chord::Chord,
    /// Where the lanes' trace was last marked ([`edge`]), world mm.
    trace_at: Option<(i32, i32)>,
    /// Where the edge pass last went on from the queue's end instead of
    /// its own last cell ([`edge`]), world mm.
    edge_rejoined_at: Option<(i32, i32)>,
    /// The planning step before which no scroll is looked for again.
    scroll_look_at: u32,
}

/// The executive at work on the caller's buffers `P` (the planning side).
struct Exec<'m, 'p, P> {
    m: &'m mut Mission,
    p: &'p mut P,
}

impl Mission {
    /// A mission waiting for [`Mission::begin`].
    pub const fn new(cfg: MissionConfig) -> Self {
        Self {
            cfg,
            drive: Drive {
                odom: Odometry::new(cfg.geometry),
                wheels: WheelControl::new(cfg.gains, (cfg.geometry.wheelbase_um / 1000) as i32),
                last_tick_us: None,
                enc_last: (0, 0),
                prev_delta: [0; 2],
                prev_dt_us: 0,
                sensed_ok: false,
                map_h_mm: 0,
            },
            lidar: LidarIn {
                parser: Ld06::new(),
                asm: ScanAssembler::new(),
                scan: Scan::new(),
                ring: lidar::HitRing::new(),
                last_frame_us: 0,
            },
            queue: SubPaths::new(),
            activity: Activity::Follow,
            cmd: (0, 0),
            dwa_cmd: (0, 0),
            apf_minimum: None,
            near_walls: NearWalls::new(),
            person_near_us: 0,
            bump_places: bump::BumpPlaces::new(),
            handoff: Handoff::new(),
            events: Events::new(),
            phase: Phase::Idle,
            halted_since: None,
            plan_due_us: 0,
            subpath_since_us: 0,
            retries: 0,
            guard_block_since: None,
            still_since_us: None,
            held_to: None,
            bumper: Bumper::RELEASED,
            avoid_since_us: 0,
            start: Pose {
                x_mm: 0,
                y_mm: 0,
                theta_mrad: 0,
            },
            edge: EdgePass::new(),
            planner_done: false,
            feed: None,
            route: route::Route::new(),
            in_route: false,
            map_dirty: false,
            home_requested: false,
            coarse_dirty: NO_CELLS,
            fine_stale: true,
            fine_is_edge: false,
            replan_target: None,
            replan_count: 0,
            reopens: 0,
            edge_reopens: 0,
            edge_give_ups: bump::BumpPlaces::new(),
            abandon_rounds: 0,
            skipped_goals: heapless::Vec::new(),
            boxed_wait: None,
            boxed_tries: 0,
            pocket: cover::Pocket::new(),
            plan_abandoned_seen: 0,
            late_retry: false,
            undriven_retry: false,
            home_tries: 0,
            home_best_mm: u16::MAX,
            edge_tries: 0,
            started_us: 0,
            counters: Counters::new(),
            loc: Fusion::new(),
            start_fixed: false,
            relocated: false,
            lost_since_us: 0,
            bump_replan: false,
            battery: battery::Charge::new(),
            restored: false,
            edge_progress_pending: false,
            rooms: rooms::RoomTour::new(),
            chord: crate::nav::chord::Chord::new(),
            trace_at: None,
            edge_rejoined_at: None,
            scroll_look_at: 0,
        }
    }

    /// Before [`Mission::begin`]: takes `cfg` as [`Mission::new`] would
    /// have (the odometry and the wheel controllers follow its geometry
    /// and gains). For a firmware whose mission lives in a static built
    /// with a default configuration: building a new one would need its
    /// whole size (about 20 KB) on the stack.
    pub fn configure(&mut self, cfg: MissionConfig) {
        self.cfg = cfg;
        self.drive.odom = Odometry::new(cfg.geometry);
        self.drive.wheels = WheelControl::new(cfg.gains, (cfg.geometry.wheelbase_um / 1000) as i32);
    }

    /// Starts a mission at `start` (world mm, mrad: the dock's place on
    /// the map), on an executive fresh from [`Mission::new`] (or a static's
    /// first [`Mission::configure`]): it is not reset here, since building
    /// a new one would take its whole size of stack; the firmware runs one
    /// mission per boot. Known mode: `parts.map` already holds the prior map.
    /// Unknown mode: the caller has sized `parts.map` (all unknown).
    pub fn begin(&mut self, parts: &mut (impl MissionParts + ?Sized), start: Pose) {
        parts.begin(self, start);
    }

    /// The lidar event: bytes as they arrive (`now_us` their arrival
    /// time). Per byte the parser; per frame 12 points into the ring; per
    /// revolution (unknown mode, or known mode with map updates) one
    /// ray-cast update of the evidence map.
    pub fn feed_lidar(
        &mut self,
        parts: &mut (impl MissionParts + ?Sized),
        bytes: &[u8],
        now_us: u64,
    ) {
        parts.feed_lidar(self, bytes, now_us);
    }

    /// The real-time entry point, every control period: reads the
    /// encoders' raw counts, returns the motor command. Touches no big
    /// buffer; bounded work (see the module docs).
    pub fn control(&mut self, now_us: u64, enc: (u16, u16)) -> MotorCmd {
        let cmd = match self.sense(now_us, enc) {
            Ok(s) => self.act(now_us, s),
            Err(cmd) => cmd,
        };
        self.events.track(now_us, self.state());
        cmd
    }

    /// The bumper's switches, read just before this control period's
    /// [`Mission::control`] (or [`Mission::tick`]). A closed switch while
    /// driving brakes, backs off and has the planner mark the spot.
    pub fn set_bumper(&mut self, bumper: Bumper) {
        self.bumper = bumper;
    }

    /// True when a planning step is due (and the last control period
    /// sensed normally: no planning while braked for lidar silence).
    pub fn plan_due(&self, now_us: u64) -> bool {
        self.drive.sensed_ok && now_us >= self.plan_due_us
    }

    /// The background entry point: one planning step when due (else
    /// nothing). Replays what control handed off, then searches (at most
    /// `node_budget` nodes), runs DWA, keeps the maps and decides.
    pub fn plan(&mut self, parts: &mut (impl MissionParts + ?Sized), now_us: u64) {
        if self.plan_due(now_us) {
            parts.plan(self, now_us);
            self.events.track(now_us, self.state());
        }
    }

    /// The host's lock-step control period: control's sensing half, the
    /// planning step when due, then control's acting half. The same as
    /// [`Mission::control`] followed at once by [`Mission::plan`], except
    /// that the plan's decision reaches this period's command.
    pub fn tick(
        &mut self,
        parts: &mut (impl MissionParts + ?Sized),
        now_us: u64,
        enc: (u16, u16),
    ) -> MotorCmd {
        let cmd = match self.sense(now_us, enc) {
            Ok(s) => {
                self.plan(parts, now_us);
                self.act(now_us, s)
            }
            Err(cmd) => cmd,
        };
        self.events.track(now_us, self.state());
        cmd
    }

    /// The next event, oldest first.
    pub fn pop_event(&mut self) -> Option<Event> {
        self.events.pop()
    }

    /// The configuration.
    pub fn config(&self) -> &MissionConfig {
        &self.cfg
    }

    /// The odometry pose.
    pub fn pose(&self) -> Pose {
        self.drive.odom.pose()
    }

    /// Event counters.
    pub fn counters(&self) -> Counters {
        Counters {
            events_dropped: self.events.dropped,
            ..self.counters
        }
    }

    /// The lidar parser's counters.
    pub fn parser_stats(&self) -> crate::robot::lidar::ParserStats {
        self.lidar.parser.stats()
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
            Phase::Charging { .. } => State::Charging,
            Phase::Idle
            | Phase::SelfTestScan { .. }
            | Phase::SelfTestWheels { .. }
            | Phase::SelfTestSettle { .. } => State::SelfTest,
            _ if self.loc.lost => State::Relocalising,
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
                    Phase::Align => State::Docking,
                    _ => State::Return,
                },
            },
        }
    }

    /// Where the mission began (the dock), as the start's relocalisation
    /// left it: what a saved map keeps ([`crate::robot::map_image`]).
    pub fn dock(&self) -> Pose {
        self.start
    }

    /// True once the mission is over (done or failed).
    pub fn finished(&self) -> bool {
        matches!(self.phase, Phase::Done | Phase::Failed(_))
    }
}
