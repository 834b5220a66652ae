//! The hand-off from the real-time control path to the planning path:
//! what control did that the planner's buffers must learn of. Control
//! touches no big buffer (no planner, grid or map), so on the robot it
//! never waits for the planning task; the planning step replays the notes
//! in order before it plans ([`super::Exec::drain`]), which gives exactly
//! the result of applying them at once (nothing reads what they change in
//! between).
//!
//! **Capacity.** [`HANDOFF`] notes. A planning cell swept is noted once
//! per run of ticks in it, and a sub-path given up at most once per tick,
//! so at 100 Hz control and 10 Hz planning at most ten notes wait. If the
//! planning task falls far behind and the hand-off fills, further notes are
//! dropped and counted (`Counters::handoff_dropped`, and a capacity event):
//! a lost "swept" mark only lets a cell be retried, a lost give-up only
//! leaves its cells for the rescan.

use crate::nav::follow::SubPath;
use crate::robot::odometry::Pose;
use heapless::Vec;

/// Notes held between two planning steps.
pub const HANDOFF: usize = 32;

/// One thing control did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Note {
    /// The robot stood in this planning cell while cleaning.
    Swept((i32, i32)),
    /// Control gave up the sub-path `seg` (`cover`: a cleaning move);
    /// `stalled`: after repeated wheel stalls. `last_end`: where the
    /// queue ended then.
    GaveUp {
        seg: SubPath,
        cover: bool,
        stalled: bool,
        last_end: Option<(i32, i32)>,
    },
    /// The bumper closed at `at_us`, at `pose`, the contact `bearing_mrad`
    /// from the heading ([`crate::robot::hal::Bumper::bearing_mrad`]).
    Bumped {
        at_us: u64,
        pose: Pose,
        bearing_mrad: i32,
    },
    /// A wheel (`left`, else the right) stalled at `at_us`, at `pose`,
    /// with nothing the lidar sees against the body: a cable or a rug's
    /// edge under it.
    Stalled { at_us: u64, pose: Pose, left: bool },
}

/// The notes waiting for the planning step.
pub(super) struct Handoff {
    notes: Vec<Note, HANDOFF>,
    last_swept: Option<(i32, i32)>,
}

impl Handoff {
    pub(super) const fn new() -> Self {
        Self {
            notes: Vec::new(),
            last_swept: None,
        }
    }

    /// Adds a note; false when full (the note is dropped).
    pub(super) fn push(&mut self, n: Note) -> bool {
        if let Note::Swept(c) = n {
            if self.last_swept == Some(c) {
                return true;
            }
            self.last_swept = Some(c);
        }
        self.notes.push(n).is_ok()
    }

    /// Takes the notes, oldest first.
    pub(super) fn take(&mut self) -> Vec<Note, HANDOFF> {
        self.last_swept = None;
        core::mem::take(&mut self.notes)
    }
}
