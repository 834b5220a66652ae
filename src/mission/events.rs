//! What the executive reports: state changes, faults, avoidance start and
//! end, docking, capacity warnings. They wait in a bounded queue that the
//! caller drains ([`super::Mission::pop_event`]): host-sim prints them,
//! the firmware logs them through defmt.
//!
//! **Overflow policy.** The queue holds [`EVENTS`]; when it is full the
//! oldest event is dropped and counted (`Counters::events_dropped`), so
//! the newest (the most telling, a fault) always gets in. Events never
//! change what the robot does.

use super::config::{Fault, State};
use heapless::Deque;

/// Events held until the caller drains them.
pub const EVENTS: usize = 32;

/// A capacity that was exceeded without failing the mission.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Capacity {
    /// The control-to-plan hand-off was full: a note was dropped (the
    /// planning task fell behind).
    Handoff,
}

/// What happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum EventKind {
    /// The state (as [`super::Mission::state`] reports it) changed.
    State {
        /// Before.
        from: State,
        /// After.
        to: State,
    },
    /// An avoidance started.
    AvoidStarted,
    /// An avoidance ended.
    AvoidEnded,
    /// Back at the dock: the mission is done.
    Docked,
    /// The mission failed.
    Fault(Fault),
    /// A capacity was exceeded; the mission goes on.
    Capacity(Capacity),
    /// The scan matcher lost the robot (a kidnap): braking to relocalise.
    Lost,
    /// Relocalised: at the start (within the window around the dock) or
    /// over the whole map after being lost.
    Relocalised {
        /// The pose found, mm and mrad.
        x_mm: i32,
        /// North, mm.
        y_mm: i32,
        /// Heading, mrad.
        theta_mrad: i32,
        /// How far it was from the odometry's, mm (Manhattan).
        moved_mm: i32,
    },
    /// The map scrolled under the robot ([`super::scroll`]): every world
    /// point the executive knew is now at p + (dx, dy) mm.
    MapScrolled {
        /// East, mm.
        dx_mm: i32,
        /// North, mm.
        dy_mm: i32,
    },
    /// The bumper felt something while driving: the robot backs off and
    /// plans the leg again.
    Bumped {
        /// Where the contact was (on the body's rim), mm.
        x_mm: i32,
        /// North, mm.
        y_mm: i32,
        /// Evidence cells marked as walls for it (0: the lidar sees what
        /// was touched, or the spot was marked already).
        marked: u8,
    },
    /// The potential field, steering an avoidance, reached a local
    /// minimum: its force vanished short of the sub-goal
    /// ([`crate::nav::apf`]). The robot turns toward the sub-goal until
    /// the avoidance times out and the leg is planned again.
    LocalMinimum {
        /// Where the robot was, mm.
        x_mm: i32,
        /// North, mm.
        y_mm: i32,
    },
    /// A wheel stalled with nothing the lidar sees against the body (a
    /// cable, a rug's edge): the robot backs off and plans the leg again
    /// around the spot.
    WheelStalled {
        /// Where: just ahead of the stalled wheel, mm.
        x_mm: i32,
        /// North, mm.
        y_mm: i32,
        /// Evidence cells marked as walls for it (0: marked already).
        marked: u8,
    },
}

/// An event and when it happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Event {
    /// Time, µs (the caller's clock).
    pub at_us: u64,
    /// What happened.
    pub kind: EventKind,
}

/// The bounded event queue.
pub(super) struct Events {
    queue: Deque<Event, EVENTS>,
    last: State,
    pub(super) dropped: u32,
}

impl Events {
    pub(super) const fn new() -> Self {
        Self {
            queue: Deque::new(),
            last: State::SelfTest,
            dropped: 0,
        }
    }

    /// Queues an event, dropping the oldest when full.
    pub(super) fn push(&mut self, at_us: u64, kind: EventKind) {
        let e = Event { at_us, kind };
        if let Err(e) = self.queue.push_back(e) {
            self.queue.pop_front();
            self.dropped += 1;
            let _ = self.queue.push_back(e);
        }
    }

    /// Reports the change from the last state seen to `now`, if any.
    pub(super) fn track(&mut self, at_us: u64, now: State) {
        let from = self.last;
        if from == now {
            return;
        }
        self.last = now;
        self.push(at_us, EventKind::State { from, to: now });
        if from == State::Avoid {
            self.push(at_us, EventKind::AvoidEnded);
        }
        match now {
            State::Avoid => self.push(at_us, EventKind::AvoidStarted),
            State::Done => self.push(at_us, EventKind::Docked),
            State::Failed(f) => self.push(at_us, EventKind::Fault(f)),
            _ => {}
        }
    }

    pub(super) fn pop(&mut self) -> Option<Event> {
        self.queue.pop_front()
    }
}
