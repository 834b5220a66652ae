//! The mission over the sim link (processor-in-the-loop, issue 11 §4):
//! the executive, its tasks and the firmware's capacities, with host-sim
//! in place of the robot.
//!
//! Lock-step: the host sends a tick per control period (after that
//! period's lidar bytes on the lidar USART); the firmware runs the lidar
//! event, the control tick and the plan step in the firmware's order
//! ([`Mission::control`] then [`Mission::plan`]), answers with the motor
//! command, then sends the executive's events. Each task's worst case is
//! measured in instructions; at the end the report carries them with the
//! stack's high-water mark.

use super::board::meter::Meter;
use super::board::simlink::SimLink;
use super::stack;
use super::status::{self, STATUS_US};
use robovac::capacity::{
    FwEvidence, FwFineGrid, FwMatcher, FwParts, FwPlanGrid, FwPlanner, FwWindow, FW_FINE_CELLS,
    FW_FINE_PATH, FW_MISSION_BYTES, FW_PLAN_CELLS,
};
use robovac::link::msg::{unpack_cell, Down, Ready, Report, StepMsg, TaskCost, Tick, Up};
use robovac::mission::{Mission, MissionParts, MotorCmd, Reflex};

/// The robot's clock (the F411 at 84 MHz), for the reflex's hold in
/// instructions.
const CLOCK_HZ: u64 = 84_000_000;
use robovac::Cell;

/// The mission's buffers (statics of the entry point).
pub struct Buffers {
    /// The executive.
    pub mission: &'static mut Mission,
    /// The coverage planner (owner of the one search state).
    pub planner: &'static mut FwPlanner,
    /// The fine searches' window.
    pub search: &'static mut FwWindow,
    /// The planning grid.
    pub coarse: &'static mut FwPlanGrid,
    /// The fine configuration space.
    pub fine: &'static mut FwFineGrid,
    /// The evidence map.
    pub map: &'static mut FwEvidence,
    /// The fine path.
    pub path: &'static mut [Cell; FW_FINE_PATH],
    /// The scan matcher.
    pub matcher: &'static mut FwMatcher,
    /// The planning cells' rooms.
    pub rooms: &'static mut [u8; FW_PLAN_CELLS],
}

/// Waits for a Hello from the host and runs its mission; then resets the
/// chip (one mission per boot).
pub fn run(b: Buffers, link: &mut SimLink, meter: &Meter) -> ! {
    link.send(&Up::Ready(Ready {
        map_cells: FW_FINE_CELLS as u32,
        mission_bytes: FW_MISSION_BYTES as u32,
    }));
    loop {
        let Down::Hello(h) = link.recv() else {
            continue;
        };
        if b.map
            .reset(h.map_w as u32, h.map_h as u32, h.res_mm as u32)
            .is_err()
        {
            link.send(&Up::Refused);
            continue;
        }
        defmt::info!("mission: {}x{} cells", h.map_w, h.map_h);
        if !load_map(b.map, link) {
            continue;
        }
        b.mission.configure(h.cfg);
        b.planner.set_kind(h.cfg.kind);
        let mut parts = FwParts {
            planner: &mut *b.planner,
            search: &mut *b.search,
            coarse: &mut *b.coarse,
            fine: &mut *b.fine,
            map: &mut *b.map,
            path: &mut b.path[..],
            matcher: &mut *b.matcher,
            rooms: &mut b.rooms[..],
        };
        defmt::info!("map loaded; mission begins");
        b.mission.begin(&mut parts, h.dock);
        defmt::info!("begun");
        let worst = periods(b.mission, &mut parts, link, meter);
        report(b.mission, link, worst);
        // One mission per boot: the executive is not reset in place.
        cortex_m::peripheral::SCB::sys_reset();
    }
}

/// Map rows until Start (false when the host sent something else).
fn load_map(map: &mut FwEvidence, link: &mut SimLink) -> bool {
    loop {
        match link.recv() {
            Down::MapRow { row, cells } => {
                let w = map.width() as usize;
                for x in 0..w.min(cells.len() * 4) {
                    map.set_state(x as i32, row as i32, unpack_cell(&cells, x));
                }
            }
            Down::Start => return true,
            _ => return false,
        }
    }
}

/// Control periods until the host ends the mission. Events go to the
/// host and to the log, with a status line every few seconds.
fn periods(
    m: &mut Mission,
    parts: &mut FwParts<'_>,
    link: &mut SimLink,
    meter: &Meter,
) -> TaskCost {
    let mut tally = Tally::default();
    let mut bytes = [0u8; 1024];
    let mut next_status = STATUS_US;
    loop {
        let t = match link.recv() {
            Down::Tick(t) => t,
            Down::Home => {
                m.request_home();
                continue;
            }
            Down::End => return tally.worst,
            _ => continue,
        };
        let step = period(m, parts, link, meter, &t, &mut bytes, &mut tally);
        link.send(&Up::Step(step));
        while let Some(e) = m.pop_event() {
            status::event(&e);
            link.send(&Up::Event(e));
        }
        if t.t_us >= next_status {
            next_status = t.t_us + STATUS_US;
            status::status(t.t_us, m, parts.coarse);
        }
    }
}

/// The tasks' costs so far, and whether the robot is driving.
#[derive(Default)]
struct Tally {
    worst: TaskCost,
    driving: bool,
}

impl Tally {
    /// Counts a step that held the executive past the reflex's hold
    /// while the robot was driving (`lidar`: a lidar event, else a plan
    /// step): on the robot, control would brake for the rest of it.
    fn note_hold(&mut self, insn: u64, lidar: bool) -> bool {
        let hold = Reflex::hold_instructions(CLOCK_HZ);
        if !self.driving || insn <= hold {
            return false;
        }
        let w = &mut self.worst;
        if lidar {
            w.lidar_over_hold += 1;
        } else {
            w.plan_over_hold += 1;
        }
        w.braked_insn += insn - hold;
        true
    }
}

/// One period: the lidar event, the control tick, the plan step.
fn period<P: MissionParts>(
    m: &mut Mission,
    parts: &mut P,
    link: &mut SimLink,
    meter: &Meter,
    t: &Tick,
    bytes: &mut [u8; 1024],
    tally: &mut Tally,
) -> StepMsg {
    let ms = t.t_us / 1000;
    let n = link.lidar_bytes(t.lidar_bytes as usize, bytes);
    let (_, c) = meter.measure(|| m.feed_lidar(parts, bytes.get(..n).unwrap_or(&[]), t.t_us));
    if tally.note_hold(c, true) {
        defmt::info!(
            "t {} ms: lidar event of {} instructions held past the hold",
            ms,
            c
        );
    }
    tally.worst.total_insn += c;
    if c > tally.worst.lidar {
        tally.worst.lidar = c;
        defmt::info!("t {} ms: worst lidar event {} instructions", ms, c);
    }
    m.set_bumper(t.bumper);
    let (cmd, c) = meter.measure(|| m.control(t.t_us, t.enc));
    tally.worst.total_insn += c;
    if c > tally.worst.control {
        tally.worst.control = c;
        defmt::info!("t {} ms: worst control tick {} instructions", ms, c);
    }
    let (before, state) = (m.counters(), m.state());
    let (_, c) = meter.measure(|| m.plan(parts, t.t_us));
    if tally.note_hold(c, false) {
        log_held_plan(ms, c, state, &before, m, parts);
    }
    tally.worst.total_insn += c;
    tally.driving = matches!(cmd, MotorCmd::Duty(l, r) if l != 0 || r != 0);
    if c > tally.worst.plan {
        tally.worst.plan = c;
        let state = defmt::Debug2Format(&m.state());
        defmt::info!(
            "t {} ms: worst plan step {} instructions ({})",
            ms,
            c,
            state
        );
    }
    StepMsg {
        cmd,
        state: m.state(),
        pose: m.pose(),
        lost: m.lost(),
        avoidance_events: m.counters().avoidance_events,
        finished: m.finished(),
    }
}

/// A plan step that held the executive past the reflex's hold while the
/// robot drove, with what it did (for finding what to bound next).
fn log_held_plan<P: MissionParts>(
    ms: u64,
    insn: u64,
    state: robovac::mission::State,
    before: &robovac::mission::Counters,
    m: &Mission,
    parts: &P,
) {
    let after = m.counters();
    defmt::info!(
        "t {} ms: plan step of {} instructions held past the hold ({} -> {}): detours +{}, routes +{}, replans +{}, avoidances +{}, planner nodes {}",
        ms,
        insn,
        defmt::Debug2Format(&state),
        defmt::Debug2Format(&m.state()),
        after.detours.wrapping_sub(before.detours),
        after.routes.wrapping_sub(before.routes),
        after.replans.wrapping_sub(before.replans),
        after.avoidance_events.wrapping_sub(before.avoidance_events),
        parts.planner_view().last_step_nodes
    );
}

/// The end-of-mission report.
fn report(m: &Mission, link: &mut SimLink, worst: TaskCost) {
    let used = stack::used();
    defmt::info!(
        "mission over: {}; worst control {} lidar {} plan {} instructions; stack {} of {} bytes",
        defmt::Debug2Format(&m.state()),
        worst.control,
        worst.lidar,
        worst.plan,
        used,
        stack::size()
    );
    link.send(&Up::Report(Report {
        counters: m.counters(),
        loc: m.loc_stats(),
        parser: m.parser_stats(),
        edge: m.edge_stats(),
        link: link.link_stats(),
        rx_errors: link.rx_counts().0,
        rx_dropped: link.rx_counts().1,
        log_dropped: super::log::dropped(),
        worst,
        stack_used: used as u32,
        stack_size: stack::size() as u32,
    }));
}
