//! What the control period does when it cannot reach the executive.
//!
//! On the robot (firmware/app.rs) the executive is shared without
//! blocking: a planning step or a lidar event holds it, and a control
//! period that falls due meanwhile does not wait for it (a planning step
//! may take hundreds of milliseconds: up to 31 M instructions, 372 ms at
//! 84 MHz, in the whole emulated studio mission). Control then runs this
//! reflex instead of [`super::Mission::control`]:
//!
//! - within [`Reflex::HOLD_US`] of the last command it keeps that command
//!   (a lidar event or a short planning step ends within a period or two);
//! - past it, it brakes: the robot never drives on unguarded for more
//!   than `HOLD_US` (at 0.3 m/s, 18 mm);
//! - it feeds the watchdog (control alive, motors safe) until the
//!   executive has been held for [`Reflex::HUNG_US`]; a step that never
//!   ends then lets the watchdog reset the chip.
//!
//! When the executive comes free, control runs it again: the odometry
//! takes the encoder counts gathered meanwhile as one longer period.

use super::MotorCmd;

/// The control period's fallback while the executive is held elsewhere.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reflex {
    last: MotorCmd,
    last_ran_us: u64,
}

/// What the reflex decided for one control period.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReflexOut {
    /// The motor command.
    pub cmd: MotorCmd,
    /// Whether to feed the watchdog.
    pub feed: bool,
}

impl Reflex {
    /// The last command is kept this long without the executive: longer
    /// than a lidar revolution's event (the scan matched and ray-cast:
    /// about 3.7 M instructions, 44 ms at 84 MHz, on average in the
    /// emulated studio, so a hold of 25 ms braked the robot at every
    /// revolution), shorter than the lidar's own 100 ms revolution that
    /// the guard's points already lag by.
    pub const HOLD_US: u64 = 60_000;
    /// Held longer than this, the executive is taken for hung: the
    /// watchdog is no longer fed. Longer than the longest measured step
    /// that holds it (a whole-map relocalisation after a kidnap: 75.7 M
    /// instructions, 0.9 s at 84 MHz on a 48 m² flat, about 2.7 s on a
    /// 12 × 12 m home).
    pub const HUNG_US: u64 = 6_000_000;

    /// A reflex that has seen no command yet (it brakes).
    pub const fn new() -> Self {
        Self {
            last: MotorCmd::Brake,
            last_ran_us: 0,
        }
    }

    /// Control ran the executive at `now_us` and sent `cmd`.
    pub fn ran(&mut self, now_us: u64, cmd: MotorCmd) {
        self.last = cmd;
        self.last_ran_us = now_us;
    }

    /// Control could not reach the executive at `now_us`.
    pub fn busy(&mut self, now_us: u64) -> ReflexOut {
        let held_us = now_us.saturating_sub(self.last_ran_us);
        if held_us > Self::HOLD_US {
            self.last = MotorCmd::Brake;
        }
        ReflexOut {
            cmd: self.last,
            feed: held_us <= Self::HUNG_US,
        }
    }

    /// Instructions at `clock_hz` that a step holding the executive may
    /// take before the reflex brakes (for the measured runs' counts).
    pub const fn hold_instructions(clock_hz: u64) -> u64 {
        clock_hz / 1000 * Self::HOLD_US / 1000
    }
}

impl Default for Reflex {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DRIVE: MotorCmd = MotorCmd::Duty(300, 280);

    #[test]
    fn keeps_the_last_command_for_a_short_hold() {
        let mut r = Reflex::new();
        r.ran(1_000_000, DRIVE);
        let out = r.busy(1_010_000);
        assert_eq!(
            out,
            ReflexOut {
                cmd: DRIVE,
                feed: true
            }
        );
        assert_eq!(r.busy(1_000_000 + Reflex::HOLD_US).cmd, DRIVE);
    }

    #[test]
    fn brakes_past_the_hold_and_stays_braked() {
        let mut r = Reflex::new();
        r.ran(1_000_000, DRIVE);
        assert_eq!(r.busy(1_000_000 + Reflex::HOLD_US + 1).cmd, MotorCmd::Brake);
        // Braked once, it does not drive again until the executive runs.
        assert_eq!(r.busy(1_000_000 + Reflex::HOLD_US + 1).cmd, MotorCmd::Brake);
        r.ran(2_000_000, DRIVE);
        assert_eq!(r.busy(2_010_000).cmd, DRIVE);
    }

    #[test]
    fn stops_feeding_the_watchdog_when_hung() {
        let mut r = Reflex::new();
        r.ran(0, DRIVE);
        assert!(r.busy(Reflex::HUNG_US).feed);
        let out = r.busy(Reflex::HUNG_US + 1);
        assert_eq!(
            out,
            ReflexOut {
                cmd: MotorCmd::Brake,
                feed: false
            }
        );
    }

    #[test]
    fn a_fresh_reflex_brakes() {
        assert_eq!(Reflex::new().busy(0).cmd, MotorCmd::Brake);
    }

    #[test]
    fn hold_in_instructions_at_84_mhz() {
        assert_eq!(Reflex::hold_instructions(84_000_000), 5_040_000);
    }
}
