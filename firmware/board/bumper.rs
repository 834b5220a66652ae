//! The front bumper's two microswitches on GPIO inputs with pull-ups
//! (closed: the pin reads low), behind the core's `BumperSwitches`.
//! Read once per control period; the switch's own travel holds a contact
//! closed for many periods, so no debouncing is needed to see it.

use super::wiring::{BumperLeftPin, BumperRightPin, BUMPER_ACTIVE_LOW};
use robovac::robot::hal::{Bumper, BumperSwitches};

/// The two switches.
pub struct Switches {
    left: BumperLeftPin,
    right: BumperRightPin,
}

impl Switches {
    /// Takes the two pins, already configured as pulled-up inputs.
    pub fn new(left: BumperLeftPin, right: BumperRightPin) -> Self {
        Self { left, right }
    }
}

impl BumperSwitches for Switches {
    fn read_bumper(&mut self) -> Bumper {
        Bumper {
            left: self.left.is_low() == BUMPER_ACTIVE_LOW,
            right: self.right.is_low() == BUMPER_ACTIVE_LOW,
        }
    }
}
