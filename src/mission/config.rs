//! The executive's vocabulary: map modes, faults, states, the motor
//! command, every tunable ([`MissionConfig`]) and the counters. A leaf of
//! the mission layer.

use crate::coverage::PlannerKind;
use crate::nav::apf::{ApfParams, DEFAULT_APF};
use crate::nav::dwa::{self, DwaParams};
use crate::nav::follow::FollowParams;
use crate::nav::guard::GuardParams;
use crate::nav::keep_off::KeepOffParams;
use crate::robot::lidar_map::LidarMount;
use crate::robot::odometry::DriveGeometry;
use crate::robot::wheel_control::WheelGains;

/// Lidar hit points kept (world mm): a little over one revolution.
pub const RING: usize = 512;
/// Frames per lidar revolution held by the scan assembler.
pub const SCAN_FRAMES: usize = 48;
/// Straight sub-paths queued ahead of the robot.
pub const QUEUE: usize = 48;
/// Grid obstacles near the robot offered to DWA besides the lidar points.
pub(super) const MAP_POINTS: usize = 64;
/// Starts of the edge pass tried while the robot is boxed in on the map
/// (one per planning step, 10 Hz): 30 s for whoever stands beside it to
/// move on, after which the pass is skipped or ends where it stands
/// ([`super::edge`]).
pub const EDGE_TRIES: u16 = 300;
/// Plans of the way home tried (one per planning step, 10 Hz) before the
/// mission fails with [`Fault::NoWayHome`]: two minutes. A person who
/// follows the robot about at the end of a mission (walking into it, so
/// the bumper marks the spot) kept it boxed in for longer than the 30 s
/// it once waited (S6 home, unknown mode, realistic noise, 1 person,
/// seed 2: failed 67 s after turning home, 4 m from the dock). A robot
/// vacuum waits for them to leave.
pub const RETURN_TRIES: u16 = 1200;
/// A cleaning detour's search that found no way having expanded fewer
/// nodes than this (fine cells, 50 mm: a region of 0.5 m² for the robot's
/// centre) found the robot boxed in, not the goal out of reach: a person
/// stands beside it against a wall, or in the doorway of a small room.
/// The l10su home, known map, 1 person, realistic noise, seed 3: a person
/// stood 0.4 m from the robot by a wall for 45 s, and every goal the
/// planner offered meanwhile (10 a second) was skipped: 150 goals, of
/// which the 16 [`SKIPPED_GOALS`] keep came back, and a room was left
/// unswept (93.9 % covered).
pub const BOXED_NODES: u32 = 200;
/// The same for the coverage planner's own search for its next goal
/// (planning cells, 0.3 m: about 1.8 m² for the robot's centre). The
/// studio, known map, 3 people, realistic noise, seed 3: two people
/// stood either side of the robot; every goal search expanded 11 cells,
/// all 66 goals were given up at once, and both rounds of taking them up
/// again (`abandon_rounds`) were spent in the same second: 80.3 %
/// covered.
pub const BOXED_PLAN_NODES: u32 = 20;
/// How long a boxed-in robot waits before searching again, µs.
pub const BOXED_WAIT_US: u64 = 1_000_000;
/// Waits in a row before the goal is skipped as before (30 s: a person
/// who stays put is not waited for all day).
pub const BOXED_TRIES: u8 = 30;
/// Sub-paths given up and put back for a later pass, at most, per mission
/// (a spot a person keeps blocking is not retried for ever).
pub const MAX_RETRIES: u32 = 400;
/// Cleaning goals the fine search found no way to, kept to hand back to
/// the planner when it finishes (`Exec::hand_back_skipped`). When full,
/// later ones are not kept (counted in `Counters::skipped` all the same).
pub const SKIPPED_GOALS: usize = 16;

/// Where the map comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MapMode {
    /// A prior map is given (seed 002's setting).
    Known,
    /// The map starts empty and grows from the lidar (seed 001's setting).
    Unknown,
}

/// Why a mission failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// On the dock to recharge, the charge did not rise: the robot is
    /// off the charger's contacts (or the charger is off).
    NotCharging,
    /// Lost (kidnapped) and not relocalised within `lost_timeout_us`.
    Lost,
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
            Fault::NotCharging => "on the dock, not charging",
            Fault::Lost => "lost: relocalisation failed",
        }
    }
}

/// What the executive is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// At the dock, turning to the heading it left with.
    Docking,
    /// On the dock, charging, to go on cleaning where it stopped.
    Charging,
    /// Motors stopped: the lidar is silent.
    LidarSilent,
    /// Motors stopped: the robot is lost (picked up and put down
    /// elsewhere) and relocalises over the whole map.
    Relocalising,
    /// Mission complete, back at the start.
    Done,
    /// Mission aborted.
    Failed(Fault),
}

/// Motor output for this tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MotorCmd {
    /// Duties, permille.
    Duty(i16, i16),
    /// Brake both motors.
    Brake,
}

/// Everything tunable, units in the names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MissionConfig {
    /// Map mode.
    pub mode: MapMode,
    /// The map an earlier run saved ([`crate::robot::map_image`]) was
    /// loaded before the mission began. Used with [`MapMode::Unknown`]:
    /// the robot localises against it and plans over it from the start,
    /// and keeps mapping. Its first revolution relocalises the dock pose
    /// within the start window, as known mode does. (Frozen as a floor
    /// plan, a saved map's walls a cell off where the first run drifted
    /// could never be corrected: the robot pressed against a door frame
    /// that stood a cell further out, or lost itself where few walls were
    /// certain enough to freeze.) Walls it holds frozen (saved by a
    /// known-mode run, or a bumper's marks) are thawed into ordinary ones
    /// when the mission begins
    /// ([`crate::robot::lidar_map::EvidenceMap::thaw_prior`]).
    pub prior_saved: bool,
    /// Unknown mode on an empty map: the map scrolls when the robot nears
    /// its edge ([`super::scroll`]). For a map in the robot's own frame
    /// (the robot image's, centred on the dock); off for a map that holds
    /// the whole home already.
    pub scroll_map: bool,
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
    /// Which local planner steers an avoidance: DWA (the default) or the
    /// potential field, for comparison (issue 13).
    pub local: LocalPlanner,
    /// The potential field, when it steers.
    pub apf: ApfParams,
    /// Guard.
    pub guard: GuardParams,
    /// Steering off walls beside the body ([`crate::nav::keep_off`]) on
    /// the cleaning legs.
    pub keep_off: KeepOffParams,
    /// The same on the legs that clean nothing (transits between lanes
    /// and contours, the way home), where the floor along the wall does
    /// not matter and the body may keep farther off.
    pub keep_off_transit: KeepOffParams,
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
    /// battery's share for cleaning), µs. Used only while no state of
    /// charge is given ([`super::Mission::set_charge`]); with one, the
    /// charge decides ([`BatteryParams`]).
    pub battery_us: u64,
    /// Going home to recharge, and resuming.
    pub battery: BatteryParams,
    /// Closer than this to two lidar points (beyond the radius), the robot
    /// stops turning and backs straight away from them, mm.
    pub escape_mm: i32,
    /// Correct the odometry by matching every revolution against the map
    /// ([`crate::localize`]); off: odometry alone.
    pub localize: bool,
    /// Lost for this long without relocalising fails the mission, µs.
    pub lost_timeout_us: u64,
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
        let mut apf = DEFAULT_APF;
        apf.radius_mm = dwa.radius_mm;
        apf.v_max_mm_s = dwa.v_max_mm_s;
        // Inside the plans' 10 mm margin, so a lane along a wall is not
        // pushed off; 40 mrad/s per mm turns a body touching the wall away
        // at 0.3 rad/s. In unknown mode the walls are the robot's own map,
        // jagged where beams graze them: from 8 mm, pushing off them cost
        // floor along every wall (l10su, realistic noise, 1 person, seed
        // 4: 96.35 -> 91.47 %). From 4 mm it acts only on a body about to
        // touch: the last grazes of the real homes (4 in 54 unknown-mode
        // missions, realistic, 1 person, seeds 1-9) were lanes begun
        // after a turn in place, whose heading error (up to the follower's
        // 100 mrad) carried the body 10-15 mm off its line onto a corner
        // the lane passed 10 mm from. With it those four missions had no
        // collision, nor had any of the 54.
        let keep_off = KeepOffParams {
            keep_mm: if matches!(mode, MapMode::Known) { 8 } else { 4 },
            gain_mrad_s_per_mm: 40,
            max_w_mrad_s: 600,
            slow_mm_s: 60,
        };
        Self {
            mode,
            prior_saved: false,
            scroll_map: false,
            kind: PlannerKind::BOha,
            geometry,
            gains,
            radius_mm,
            margin_mm: 10,
            plan_cell_mm: 300,
            // Tighter than the drive defaults: a cleaning run keeps 10 mm
            // from walls, so sub-paths end within 10 mm and the robot turns
            // to within 0.1 rad before it drives.
            //
            // Brisker than the drive defaults (issue 12's time): with 1.2
            // rad/s, a heading gain of 2.5 /s and 0.4 m/s² braking, half of
            // a mission was spent below 5 cm/s turning in place (S8 home,
            // known, realistic noise: 1,356 of 2,742 s), most of it in the
            // gain's slow tail below 0.5 rad of error. 2.5 rad/s (the
            // wheels at ±0.29 m/s of their 0.5), a gain of 8 /s (crossover
            // well below the motors' 60 ms lag) and 0.7 m/s² braking: the
            // six real homes, known and unknown, realistic noise, 1 person,
            // seed 1, took 21-45 % less time with the same coverage
            // (within 0.4 points), 0 collisions, all docked.
            follow: FollowParams {
                arrive_mm: 10,
                turn_in_place_mrad: 100,
                min_mm_s: 30,
                max_w_mrad_s: 2500,
                k_heading_x1000: 8000,
                decel_mm_s2: 700,
                ..crate::nav::follow::DEFAULT_FOLLOW
            },
            dwa,
            local: LocalPlanner::Dwa,
            apf,
            guard: GuardParams {
                radius_mm: radius_mm + 2,
                brake_mm_s2: 500,
                reserve_mm: 20,
                creep_mm_s: 40,
                moving_margin_mm: 60,
                mapped_slack_mm: 0,
            },
            keep_off,
            // Transits: the plans put them 10 mm off walls (their A*
            // hugs the configuration space's rim) and the follower strays
            // 12-17 mm from its line where a leg starts: 10 of the 13
            // grazes left on the real homes (realistic noise, 1 person,
            // 108 missions) were on such legs. Here the spring acts from
            // 20 mm, in both modes: the jagged walls of unknown mode cost
            // no floor on a leg that cleans nothing. The same 108
            // missions: 8 collisions instead of 13.
            keep_off_transit: KeepOffParams {
                keep_mm: 20,
                ..keep_off
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
            battery: BatteryParams::DEFAULT,
            map_known_updates: true,
            localize: true,
            lost_timeout_us: 60_000_000,
        }
    }

    /// Margins for a lidar whose range noise is `noise_mm` (1 σ): the
    /// clearance kept from mapped walls grows by 2 σ and the guard's
    /// corridor by 1.5 σ, so passing a wall does not look like driving
    /// into it and a noisy wall is not grazed. 0 for an ideal sensor.
    pub const fn with_lidar_noise(mut self, noise_mm: i32) -> Self {
        if self.localize {
            return self.with_localized_noise(noise_mm);
        }
        self.margin_mm = 10 + 2 * noise_mm;
        self.guard.radius_mm = self.radius_mm + 2 + noise_mm * 3 / 2;
        self.escape_mm = 2 + noise_mm / 2;
        self.dwa.radius_mm = self.radius_mm + 15 + noise_mm;
        self.apf.radius_mm = self.dwa.radius_mm;
        self
    }
}

impl MissionConfig {
    /// Half-width of the body's sweep (mm) that every straight move, chord
    /// and shortcut is checked with against the map: the radius and half
    /// the margin. The positions themselves keep the whole margin (the
    /// configuration space), so a line between two of them may cut a
    /// little inside it.
    pub const fn sweep_mm(&self) -> i64 {
        (self.radius_mm + self.margin_mm / 2) as i64
    }

    /// The margins when the pose is corrected by scan matching: the
    /// planned clearance from mapped walls stays the ideal sensor's (the
    /// walls are where the map says and the pose within a few mm; 2 mm
    /// more turned a whole ring of 5 cm cells along every wall into
    /// blocked space, and the edge pass missed that strip: 9 % of the
    /// floor). The escape judges points the map explains (walls) 1 σ
    /// closer in, so a wall passed 10 mm away does not stop every move
    /// with its noisy returns (it did: 200 000 guard ticks and 160 000
    /// escape ticks in one mission; 2 σ was faster but let the body touch
    /// a table leg's corner on a real map, 28 times in one mission). The
    /// guard judges mapped hits at full width
    /// ([`crate::nav::guard::MappedFree`]: wall points carry no noise);
    /// unmapped points (people, a moved chair) keep the full corridor and
    /// the moving margin. Its corridor is the body + 2 mm. Tried and
    /// rejected: + 5 mm (the homes bench, 108 missions: 1 collision
    /// instead of 3, but cleaning time + 8 %, avoidances doubled, and the
    /// worst coverage 91.6 % known and 92.4 % unknown).
    pub const fn with_localized_noise(mut self, noise_mm: i32) -> Self {
        self.margin_mm = 10;
        self.guard.radius_mm = self.radius_mm + 2;
        self.guard.mapped_slack_mm = noise_mm;
        self.escape_mm = 2;
        self.dwa.radius_mm = self.radius_mm + 15 + noise_mm;
        self.apf.radius_mm = self.dwa.radius_mm;
        self
    }
}

/// When to go home to recharge, and when to go on (issue 12's recharge
/// and resume; the rule is in `mission::battery`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BatteryParams {
    /// Charge kept in hand on arrival at the dock, ‰.
    pub reserve_pm: u16,
    /// The drain assumed while driving home, ‰ per minute, until the
    /// mission has measured a higher one.
    pub drain_pm_per_min: u16,
    /// The way home's length as a share of the straight line, %.
    pub home_detour_pct: u16,
    /// The speed assumed on the way home, mm/s.
    pub home_speed_mm_s: u16,
    /// Charged to this, the robot goes on cleaning, ‰.
    pub resume_pm: u16,
    /// On the dock this long with the charge not rising by 2 %: the
    /// robot is off its contacts, and the mission fails, µs.
    pub charge_timeout_us: u64,
}

impl BatteryParams {
    /// For the reference robot's 4S pack (75–80 min of cleaning from
    /// full): 6 % in hand; 14 ‰ a minute (1 000 ‰ in 71 min, a little
    /// faster than the cleaning drain, for the slopes of the way home);
    /// the way home twice the straight line (rooms and doors between),
    /// driven at 0.2 m/s with its turns; resume at 80 % (the constant-
    /// current part of a Li-ion charge: the last 20 % take as long again
    /// at a tapering current, so robot vacuums resume there); 10 min to
    /// see the charge rise.
    pub const DEFAULT: Self = Self {
        reserve_pm: 60,
        drain_pm_per_min: 14,
        home_detour_pct: 200,
        home_speed_mm_s: 200,
        resume_pm: 800,
        charge_timeout_us: 600_000_000,
    };
}

/// The local planner that steers an avoidance ([`super::avoid`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LocalPlanner {
    /// The dynamic window ([`crate::nav::dwa`]), seed 002's.
    #[default]
    Dwa,
    /// The artificial potential field ([`crate::nav::apf`]), seed 004's;
    /// its local minima are counted (`Counters::apf_minima`) and logged.
    Apf,
}

/// Event counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Counters {
    /// Avoidances started.
    pub avoidance_events: u32,
    /// DWA cycles with no admissible motion.
    pub dwa_no_admissible: u32,
    /// Lidar silences that stopped the motors.
    pub lidar_silences: u32,
    /// Wheel stalls.
    pub stalls: u32,
    /// Bumper contacts while driving (each brakes and backs off).
    pub bumps: u32,
    /// Evidence cells marked as walls where the bumper felt something the
    /// lidar did not see.
    pub bump_marks: u32,
    /// Evidence cells marked as walls where a wheel stalled with nothing
    /// in sight (a cable, a rug's edge).
    pub stall_marks: u32,
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
    /// Legs planned again because the map, as it grew, came to block
    /// them ([`super::Mission`]'s corridor watch).
    pub stale_legs: u32,
    /// Missions cut short by the battery budget.
    pub battery_returns: u32,
    /// Charges: the robot went home with its battery low, charged and
    /// went on cleaning where it stopped.
    pub charges: u32,
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
    /// Control-to-planning notes dropped because the hand-off was full.
    pub handoff_dropped: u32,
    /// Events dropped because the caller did not drain the queue.
    pub events_dropped: u32,
    /// Long ways routed over the whole map in blocks: their ends did not
    /// fit in one fine search window, or the window held no way between
    /// them ([`super::route`]).
    pub routes: u32,
    /// Local minima of the potential field met while it steered (entries
    /// into one; 0 with DWA).
    pub apf_minima: u32,
    /// Rooms entered, the first one included (0 without a room tour,
    /// [`super::rooms`]).
    pub rooms_entered: u32,
}

impl Counters {
    /// All zero (usable in a `const fn`).
    pub const fn new() -> Self {
        Self {
            avoidance_events: 0,
            dwa_no_admissible: 0,
            lidar_silences: 0,
            stalls: 0,
            bumps: 0,
            bump_marks: 0,
            stall_marks: 0,
            blocked_cells: 0,
            skipped: 0,
            detours: 0,
            retried: 0,
            replans: 0,
            stale_legs: 0,
            battery_returns: 0,
            charges: 0,
            abandoned_retries: 0,
            escapes: 0,
            guard_ticks: 0,
            scans: 0,
            plan_steps: 0,
            handoff_dropped: 0,
            events_dropped: 0,
            routes: 0,
            apf_minima: 0,
            rooms_entered: 0,
        }
    }
}
