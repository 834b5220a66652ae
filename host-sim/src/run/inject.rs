//! Bad input on the wire (issue 11 §4), the same for a native mission and
//! one with the firmware in the loop: bursts of garbage in the lidar's
//! byte stream, the bytes a UART overrun loses, and garbage on the sim
//! link between frames. A stalled lidar is the mission's `lidar_gap_s`.
//!
//! QEMU's USART cannot overrun (it holds its input until the data register
//! is read), so an overrun is injected as what it does to the stream: a
//! byte lost now and then, mid-frame.

use robovac::grid::maps::SplitMix64;

/// When to inject what (sim-time windows, s, [from, to)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Faults {
    /// 64 random bytes added to each control period's lidar bytes.
    pub lidar_garbage_s: Option<(f64, f64)>,
    /// One lidar byte in every [`OVERRUN_EVERY`] lost.
    pub lidar_overrun_s: Option<(f64, f64)>,
    /// 32 random bytes and a frame delimiter on the link before each tick
    /// (processor-in-the-loop only: a native mission has no link).
    pub link_garbage_s: Option<(f64, f64)>,
}

/// Garbage bytes per control period.
pub const LIDAR_BURST: usize = 64;
/// Garbage bytes before a tick on the link.
pub const LINK_BURST: usize = 32;
/// One byte in this many is lost to an overrun.
pub const OVERRUN_EVERY: u64 = 37;

/// What was injected.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Injected {
    /// Garbage bytes put into the lidar stream.
    pub lidar_garbage_bytes: u64,
    /// Lidar bytes lost to overruns.
    pub lidar_lost_bytes: u64,
    /// Garbage bytes put on the link.
    pub link_garbage_bytes: u64,
}

/// The injector: its own random stream (the simulation's is untouched, so
/// a mission without faults is unchanged).
pub struct Injector {
    faults: Faults,
    rng: SplitMix64,
    seen: u64,
    /// Totals so far.
    pub done: Injected,
}

fn within(w: Option<(f64, f64)>, t: f64) -> bool {
    w.is_some_and(|(a, b)| t >= a && t < b)
}

impl Injector {
    /// An injector for `faults`, seeded from the mission's seed.
    pub fn new(faults: Faults, seed: u64) -> Self {
        Self {
            faults,
            rng: SplitMix64::new(seed ^ 0x1B_AD_1B_AD),
            seen: 0,
            done: Injected::default(),
        }
    }

    /// Applies the lidar faults due at `t` to one period's bytes.
    pub fn lidar(&mut self, t: f64, bytes: &mut Vec<u8>) {
        if within(self.faults.lidar_overrun_s, t) {
            let before = bytes.len();
            let mut seen = self.seen;
            bytes.retain(|_| {
                seen += 1;
                !seen.is_multiple_of(OVERRUN_EVERY)
            });
            self.seen = seen;
            self.done.lidar_lost_bytes += (before - bytes.len()) as u64;
        }
        if within(self.faults.lidar_garbage_s, t) {
            let at = (self.rng.next_u64() as usize) % (bytes.len() + 1);
            let junk: Vec<u8> = (0..LIDAR_BURST)
                .map(|_| self.rng.next_u64() as u8)
                .collect();
            bytes.splice(at..at, junk);
            self.done.lidar_garbage_bytes += LIDAR_BURST as u64;
        }
    }

    /// The garbage to put on the link before the tick at `t` (none when
    /// not due): random bytes, then a frame delimiter.
    pub fn link(&mut self, t: f64) -> Vec<u8> {
        if !within(self.faults.link_garbage_s, t) {
            return Vec::new();
        }
        let mut junk: Vec<u8> = (0..LINK_BURST).map(|_| self.rng.next_u64() as u8).collect();
        junk.push(0);
        self.done.link_garbage_bytes += junk.len() as u64;
        junk
    }
}

/// How long after a lidar silence began (at `from_s`) the true robot stood
/// still (within 5 mm for the rest of the silence, to `to_s`, and for
/// 100 ms at least), ms; None when it never did. `truth` holds a position every 10 ms from t = 0.
pub fn stop_after_silence_ms(truth: &[(f64, f64)], (from_s, to_s): (f64, f64)) -> Option<u64> {
    let a = (from_s * 100.0).round() as usize;
    let b = ((to_s * 100.0).round() as usize).min(truth.len());
    let end = *truth.get(b.checked_sub(1)?)?;
    let still_from = (a..b).find(|&i| {
        truth
            .get(i..b)
            .is_some_and(|s| s.iter().all(|p| (p.0 - end.0).hypot(p.1 - end.1) < 0.005))
    })?;
    // Still for at least 100 ms before the silence ends (the last sample
    // alone proves nothing).
    (still_from + 10 <= b).then_some(((still_from - a) * 10) as u64)
}
