//! The sim link's messages (see the module docs of [`super`]).

use crate::localize::LocStats;
use crate::mission::{Counters, Event, MissionConfig, MotorCmd, State};
use crate::nav::edge::EdgeStats;
use crate::robot::lidar::ParserStats;
use crate::robot::lidar_map::CellState;
use crate::robot::odometry::Pose;
use heapless::Vec;
use serde::{Deserialize, Serialize};

/// Bytes of one map row message: 4 cells a byte, so rows of up to 512
/// cells (25.6 m at 5 cm).
pub const MAP_ROW_BYTES: usize = 128;

/// A packed map row ([`pack_row`]).
pub type PackedRow = Vec<u8, MAP_ROW_BYTES>;

/// Host → firmware.
///
/// `Hello` carries the whole mission configuration and is the largest
/// variant by far; it comes once per mission, and a message is decoded
/// into one stack value at a time, so the other variants' unused bytes
/// cost nothing that lasts (no heap on the chip to box it in).
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Down {
    /// A mission begins: its configuration, the dock's pose and the map's
    /// size. Known mode: map rows follow, then [`Down::Start`].
    Hello(Hello),
    /// One row of the prior map (row 0 at the top), 2 bits a cell.
    MapRow {
        /// Row from the top.
        row: u16,
        /// Packed cells ([`pack_cell`]).
        cells: PackedRow,
    },
    /// The map is complete: begin the mission.
    Start,
    /// One control period.
    Tick(Tick),
    /// The robot's button: go home ([`crate::mission::Mission::request_home`]).
    Home,
    /// The mission is over (done or out of time): send the report.
    End,
}

/// What a mission needs from the host beyond the firmware's own build.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hello {
    /// The executive's configuration (the twin's robot and lidar).
    pub cfg: MissionConfig,
    /// Where the dock is, as a person gave it.
    pub dock: Pose,
    /// Evidence map width, cells.
    pub map_w: u16,
    /// Evidence map height, cells.
    pub map_h: u16,
    /// Evidence cell side, mm.
    pub res_mm: u16,
}

/// One control period, from the host.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tick {
    /// The period's time, µs.
    pub t_us: u64,
    /// Raw encoder counts, left and right.
    pub enc: (u16, u16),
    /// The bumper's switches.
    pub bumper: crate::robot::hal::Bumper,
    /// Lidar bytes the host sent for this period on the lidar UART: the
    /// firmware takes exactly these before the tick, so the run does not
    /// depend on how the two UARTs interleave.
    pub lidar_bytes: u16,
}

/// Firmware → host.
///
/// The report makes the enum 256 bytes; an `Up` lives only on the stack
/// while one message is encoded or decoded (never in a queue), and there
/// is no heap to box it in.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Up {
    /// Booted; the capacity it was built with.
    Ready(Ready),
    /// The mission cannot run here (the map is larger than the capacity).
    Refused,
    /// The answer to a tick.
    Step(StepMsg),
    /// An event of the executive.
    Event(Event),
    /// The end-of-mission report.
    Report(Report),
}

/// What the firmware was built with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ready {
    /// Largest evidence map, cells.
    pub map_cells: u32,
    /// Bytes of the mission's buffers.
    pub mission_bytes: u32,
}

/// The firmware's answer to a tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StepMsg {
    /// The motor command.
    pub cmd: MotorCmd,
    /// The executive's state after the period.
    pub state: State,
    /// Its pose estimate.
    pub pose: Pose,
    /// Localisation has lost the robot.
    pub lost: bool,
    /// Avoidances so far.
    pub avoidance_events: u32,
    /// The mission is over.
    pub finished: bool,
}

/// Worst cases of the firmware's tasks, instructions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TaskCost {
    /// The control tick (sensing and acting).
    pub control: u64,
    /// A lidar event (one period's bytes: parsing, the ring, a
    /// revolution's map update).
    pub lidar: u64,
    /// A plan step.
    pub plan: u64,
    /// Plan steps that held the executive past the control reflex's hold
    /// ([`crate::mission::Reflex::HOLD_US`] at 84 MHz) while the robot
    /// was driving: on the robot, control brakes for their remainder.
    pub plan_over_hold: u32,
    /// Lidar events likewise.
    pub lidar_over_hold: u32,
    /// The instructions of those steps past the hold: the time the robot
    /// would stand braked by the reflex, at 84 MHz.
    pub braked_insn: u64,
    /// Every task's instructions over the mission (lidar events, control
    /// ticks, plan steps): the processor's load.
    pub total_insn: u64,
}

/// The end-of-mission report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Report {
    /// The executive's counters.
    pub counters: Counters,
    /// Localisation's counters.
    pub loc: LocStats,
    /// The lidar parser's counters.
    pub parser: ParserStats,
    /// The edge pass's counters.
    pub edge: EdgeStats,
    /// The link reader's counters.
    pub link: super::LinkStats,
    /// Worst instructions per task.
    pub worst: TaskCost,
    /// Receive errors of the USARTs (overrun, framing, noise).
    pub rx_errors: u32,
    /// Bytes lost to a full receive queue.
    pub rx_dropped: u32,
    /// Log frames dropped (a nested log call).
    pub log_dropped: u32,
    /// Stack used at most, bytes (painted at boot).
    pub stack_used: u32,
    /// Stack size, bytes.
    pub stack_size: u32,
}

/// A cell state as 2 bits: unknown 0, free 1, occupied 2.
pub fn pack_cell(s: CellState) -> u8 {
    match s {
        CellState::Unknown => 0,
        CellState::Free => 1,
        CellState::Occupied => 2,
    }
}

/// The state of cell `x` of a packed row (unknown beyond it).
pub fn unpack_cell(cells: &[u8], x: usize) -> CellState {
    let b = cells.get(x / 4).copied().unwrap_or(0);
    match (b >> ((x % 4) * 2)) & 3 {
        1 => CellState::Free,
        2 => CellState::Occupied,
        _ => CellState::Unknown,
    }
}

/// Packs a row of cell states; `None` when longer than a message holds.
pub fn pack_row(states: impl IntoIterator<Item = CellState>) -> Option<PackedRow> {
    let mut v = PackedRow::new();
    for (x, s) in states.into_iter().enumerate() {
        if x % 4 == 0 {
            v.push(0).ok()?;
        }
        let last = v.last_mut()?;
        *last |= pack_cell(s) << ((x % 4) * 2);
    }
    Some(v)
}
