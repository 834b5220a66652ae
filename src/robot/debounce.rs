//! A push button read by polling, debounced: a press counts once the
//! contact has read closed for [`Debounce::POLLS`] polls in a row, and the
//! next press only after it has read open as long (contacts bounce for a
//! few milliseconds; at the control period's 100 Hz this is 30 ms).

/// The debouncer of one button.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Debounce {
    /// Polls in a row that disagreed with the settled state.
    run: u8,
    /// The settled state: true while held.
    held: bool,
}

impl Debounce {
    /// Polls in a row that settle a change.
    pub const POLLS: u8 = 3;

    /// A button settled open.
    pub const fn new() -> Self {
        Self {
            run: 0,
            held: false,
        }
    }

    /// One poll (`closed`: the contact reads closed). True once per press,
    /// when it settles closed.
    pub fn poll(&mut self, closed: bool) -> bool {
        if closed == self.held {
            self.run = 0;
            return false;
        }
        self.run += 1;
        if self.run < Self::POLLS {
            return false;
        }
        self.run = 0;
        self.held = closed;
        closed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn presses(polls: &[bool]) -> usize {
        let mut d = Debounce::new();
        polls.iter().filter(|&&c| d.poll(c)).count()
    }

    #[test]
    fn a_clean_press_counts_once() {
        assert_eq!(
            presses(&[false, true, true, true, true, true, false, false, false]),
            1
        );
    }

    #[test]
    fn bounces_do_not_count() {
        // Closed for fewer than three polls at a time.
        assert_eq!(presses(&[true, false, true, true, false, true, false]), 0);
    }

    #[test]
    fn a_bouncing_press_counts_once_and_a_second_press_again() {
        let polls = [
            true, false, true, true, true, false, true, true, true, false, false, false, true,
            true, true,
        ];
        assert_eq!(presses(&polls), 2);
    }

    #[test]
    fn a_short_release_is_no_second_press() {
        let polls = [true, true, true, false, false, true, true, true];
        assert_eq!(presses(&polls), 1);
    }
}
