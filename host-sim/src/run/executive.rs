//! Who runs the mission in a host mission: the core's executive in this
//! process ([`Native`]), or the firmware image in the emulator over the
//! sim link ([`super::pil::Pil`]). The loop, the physics and the
//! measurements are the same for both.

use crate::io::store::MemStore;
use robovac::localize::LocStats;
use robovac::mission::{Bumper, Counters, Event, Mission, MissionParts, MotorCmd, State};
use robovac::robot::lidar::ParserStats;
use robovac::robot::odometry::Pose;

use super::mission_debug::{debug_collision, debug_fine, debug_grid, debug_tick};
use crate::sim::robot::Sim;

/// What the robot's sensors gave in one control period.
pub struct Sensors<'a> {
    /// The period's time, µs.
    pub t_us: u64,
    /// The lidar bytes that arrived in it (possibly none).
    pub lidar: &'a [u8],
    /// The encoders' raw counts.
    pub enc: (u16, u16),
    /// The bumper's switches.
    pub bumper: Bumper,
    /// The battery gauge's state of charge, ‰ (None: no gauge).
    pub charge_pm: Option<u16>,
}

/// The executive as the mission loop sees it.
pub trait Executive {
    /// Starts the mission at the dock's given pose.
    fn begin(&mut self, dock: Pose) -> Result<(), String>;
    /// One control period's sensors in; the motor command.
    fn period(&mut self, s: &Sensors<'_>) -> Result<MotorCmd, String>;
    /// Bytes of line noise on the link before the next tick (the link's
    /// bad-input test; a native executive has no link: ignored).
    fn link_noise(&mut self, _bytes: &[u8]) -> Result<(), String> {
        Ok(())
    }
    /// The robot's button: go home.
    fn request_home(&mut self) -> Result<(), String>;
    /// The next event, oldest first.
    fn pop_event(&mut self) -> Option<Event>;
    /// The mission is over.
    fn finished(&self) -> bool;
    /// The executive's state.
    fn state(&self) -> State;
    /// Its pose estimate.
    fn pose(&self) -> Pose;
    /// Localisation has lost the robot.
    fn lost(&self) -> bool;
    /// Its counters (over the sim link, only avoidances until the end).
    fn counters(&self) -> Counters;
    /// Localisation's counters.
    fn loc_stats(&self) -> LocStats;
    /// The lidar parser's counters (over the sim link, at the end).
    fn parser_stats(&self) -> ParserStats;
    /// The mission loop has ended (the firmware sends its report).
    fn end(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// `ROBOVAC_DEBUG_TRACE` output: the grids at the start and end.
    fn debug_grid(&self, _covered: bool) {}
    /// Saves the executive's map and the dock pose on it (the map kept
    /// between runs); the bytes written.
    fn save_map(&mut self, _dock: Pose, _store: &mut MemStore) -> Result<u32, String> {
        Err("the map is not saved over the sim link yet: run without --pil".into())
    }
    /// Saves the map and the cleaning progress (for a power loss); the
    /// bytes written.
    fn save_progress(&mut self, _dock: Pose, _store: &mut MemStore) -> Result<u32, String> {
        Err("the progress is not saved over the sim link yet: run without --pil".into())
    }
    /// Restores the progress saved with the map in `store`; the planning
    /// cells marked clean.
    fn restore_progress(&mut self, _store: &mut MemStore) -> Result<u32, String> {
        Err("the progress is not restored over the sim link yet: run without --pil".into())
    }
    /// The edge pass started on a restored progress: restore its part now.
    fn wants_edge_progress(&self) -> bool {
        false
    }
    /// Restores the edge pass's saved progress; the cells marked.
    fn restore_edge_progress(&mut self, _store: &mut MemStore) -> Result<u32, String> {
        Ok(0)
    }
    /// `ROBOVAC_DEBUG_TRACE` output: a collision.
    fn debug_collision(&self, _sim: &Sim) {}
    /// `ROBOVAC_DEBUG_TRACE` output: every simulated second.
    fn debug_tick(&self, _sim: &Sim) {}
    /// `ROBOVAC_DEBUG_FINE` output: every control period in a window.
    fn debug_fine(&self, _sim: &Sim) {}
}

/// The robot's map frame against the world's: world mm = map mm +
/// `offset_mm`. Translation only: the map's axes are the world's. The
/// identity (the default) for a map sized to the world; for the robot's
/// own frame (`--dock-frame`: the dock at the map's centre) it follows
/// the map's scrolls ([`robovac::mission::scroll`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    /// World mm of the map's origin.
    pub offset_mm: (i32, i32),
    /// Times the map scrolled.
    pub scrolls: u32,
}

impl Frame {
    /// A world pose in the map's frame.
    pub fn to_map(&self, p: Pose) -> Pose {
        Pose {
            x_mm: p.x_mm - self.offset_mm.0,
            y_mm: p.y_mm - self.offset_mm.1,
            ..p
        }
    }

    /// A map pose in the world's frame.
    pub fn to_world(&self, p: Pose) -> Pose {
        Pose {
            x_mm: p.x_mm + self.offset_mm.0,
            y_mm: p.y_mm + self.offset_mm.1,
            ..p
        }
    }

    /// Follows the executive's events: a scroll moves the map's origin.
    pub fn note(&mut self, e: &Event) {
        if let robovac::mission::EventKind::MapScrolled { dx_mm, dy_mm } = e.kind {
            self.offset_mm.0 -= dx_mm;
            self.offset_mm.1 -= dy_mm;
            self.scrolls += 1;
        }
    }
}

/// The core's executive in this process, in the buffers given.
pub struct Native<'a> {
    /// The executive.
    pub mission: &'a mut Mission,
    /// Its buffers.
    pub parts: &'a mut dyn MissionParts,
    /// `control` then `plan` (the firmware's order) instead of `tick`.
    pub firmware_order: bool,
    /// The map's frame against the world's.
    pub frame: Frame,
}

impl Executive for Native<'_> {
    fn begin(&mut self, dock: Pose) -> Result<(), String> {
        self.mission.begin(self.parts, self.frame.to_map(dock));
        Ok(())
    }

    fn period(&mut self, s: &Sensors<'_>) -> Result<MotorCmd, String> {
        let (t_us, enc) = (s.t_us, s.enc);
        self.mission.set_bumper(s.bumper);
        if let Some(pm) = s.charge_pm {
            self.mission.set_charge(pm);
        }
        // In the chunks the UART model delivers (as before the sim link).
        for chunk in s.lidar.chunks(512) {
            self.mission.feed_lidar(self.parts, chunk, t_us);
        }
        Ok(if self.firmware_order {
            let cmd = self.mission.control(t_us, enc);
            self.mission.plan(self.parts, t_us);
            cmd
        } else {
            self.mission.tick(self.parts, t_us, enc)
        })
    }

    fn save_map(&mut self, dock: Pose, store: &mut MemStore) -> Result<u32, String> {
        self.parts
            .save_map(self.frame.to_map(dock), store)
            .map_err(|e| format!("map not saved: {e}"))
    }

    fn save_progress(&mut self, dock: Pose, store: &mut MemStore) -> Result<u32, String> {
        self.parts
            .save_progress(self.mission, self.frame.to_map(dock), store)
            .map_err(|e| format!("progress not saved: {e}"))
    }

    fn restore_progress(&mut self, store: &mut MemStore) -> Result<u32, String> {
        self.mission
            .restore_progress(self.parts, store)
            .map_err(|e| format!("progress not restored: {e}"))
    }

    fn wants_edge_progress(&self) -> bool {
        self.mission.wants_edge_progress()
    }

    fn restore_edge_progress(&mut self, store: &mut MemStore) -> Result<u32, String> {
        self.mission
            .restore_edge_progress(self.parts, store)
            .map_err(|e| format!("edge progress not restored: {e}"))
    }

    fn request_home(&mut self) -> Result<(), String> {
        self.mission.request_home();
        Ok(())
    }
    fn pop_event(&mut self) -> Option<Event> {
        let e = self.mission.pop_event();
        if let Some(e) = &e {
            self.frame.note(e);
        }
        e
    }
    fn finished(&self) -> bool {
        self.mission.finished()
    }
    fn state(&self) -> State {
        self.mission.state()
    }
    fn pose(&self) -> Pose {
        self.frame.to_world(self.mission.pose())
    }
    fn lost(&self) -> bool {
        self.mission.lost()
    }
    fn counters(&self) -> Counters {
        self.mission.counters()
    }
    fn loc_stats(&self) -> LocStats {
        self.mission.loc_stats()
    }
    fn parser_stats(&self) -> ParserStats {
        self.mission.parser_stats()
    }
    fn debug_grid(&self, covered: bool) {
        debug_grid(self.parts, covered);
    }
    fn debug_collision(&self, sim: &Sim) {
        debug_collision(sim, self.mission, self.parts);
    }
    fn debug_tick(&self, sim: &Sim) {
        debug_tick(sim, self.mission, self.parts);
    }
    fn debug_fine(&self, sim: &Sim) {
        debug_fine(sim, self.mission, self.parts);
    }
}
