//! LDROBOT LD06 / LD19 (also STL-19P) protocol.
//!
//! 230400 baud 8N1, transmit only. 47-byte little-endian frames:
//! `0x54`, `0x2C`, speed (u16, °/s), start angle (u16, 0.01°),
//! 12 × {distance u16 mm, intensity u8}, end angle (u16, 0.01°),
//! timestamp (u16 ms, wraps at 30000), CRC-8 over bytes 0–45 (polynomial
//! 0x4D, init 0, no reflection, no final XOR; "123456789" → 0xC3).
//! Point i's angle = start + i·((end − start + 36000) mod 36000)/11.
//!
//! The parser is a state machine fed one byte at a time (from an interrupt
//! or a DMA buffer). It looks for `0x54 0x2C`; after a complete frame it
//! checks the CRC, then plausibility: speed within
//! [`MIN_SPEED_DPS`]..=[`MAX_SPEED_DPS`], angles below 360°, an angular
//! span no wider than twelve samples at [`MIN_SAMPLE_RATE_HZ`] allow, and a
//! timestamp below 30 000 ms. (CRC-8 lets about one corrupted window in 256
//! through by chance; these checks catch most of those, and the tests
//! measure the rest.) A
//! frame that fails is never emitted; the parser then **resynchronises
//! inside the bytes it already holds** (the next `0x54` after the failed
//! header), so one corrupt byte costs at most the frame it hit.

use super::{LidarFrame, LidarPoint, LidarProtocol, ParserStats};

/// Frame length in bytes.
pub const FRAME_LEN: usize = 47;
/// Header byte.
pub const HEADER: u8 = 0x54;
/// Version/length byte (12 points).
pub const VER_LEN: u8 = 0x2C;
/// Slowest plausible rotation (1 Hz).
pub const MIN_SPEED_DPS: u16 = 360;
/// Fastest plausible rotation (20 Hz).
pub const MAX_SPEED_DPS: u16 = 7200;
/// Timestamps wrap here; a larger one is implausible.
pub const TIMESTAMP_WRAP_MS: u16 = 30_000;
/// Lowest sample rate assumed for the span check (the LD19 datasheet's own
/// example frame implies about 2 300 samples/s at 2 152 °/s).
pub const MIN_SAMPLE_RATE_HZ: u32 = 1500;

/// CRC-8, polynomial 0x4D, init 0, MSB first, no final XOR.
#[allow(clippy::indexing_slicing)] // i < 256 by the loop bound, in a const fn
pub const fn crc8_table() -> [u8; 256] {
    let mut t = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        let mut c = i as u8;
        let mut b = 0;
        while b < 8 {
            c = if c & 0x80 != 0 {
                (c << 1) ^ 0x4D
            } else {
                c << 1
            };
            b += 1;
        }
        t[i] = c;
        i += 1;
    }
    t
}

static CRC_TABLE: [u8; 256] = crc8_table();

/// CRC-8 of `data` as the LD06 computes it.
pub fn crc8(data: &[u8]) -> u8 {
    data.iter().fold(0u8, |c, &b| {
        CRC_TABLE.get((c ^ b) as usize).copied().unwrap_or(0)
    })
}

/// The LD06 parser.
#[derive(Clone, Debug)]
pub struct Ld06 {
    buf: [u8; FRAME_LEN],
    len: usize,
    stats: ParserStats,
}

impl Default for Ld06 {
    fn default() -> Self {
        Self::new()
    }
}

fn u16_at(b: &[u8; FRAME_LEN], i: usize) -> u16 {
    match (b.get(i), b.get(i + 1)) {
        (Some(&lo), Some(&hi)) => u16::from_le_bytes([lo, hi]),
        _ => 0,
    }
}

impl Ld06 {
    /// A parser waiting for a frame start.
    pub const fn new() -> Self {
        Self {
            buf: [0; FRAME_LEN],
            len: 0,
            stats: ParserStats {
                frames: 0,
                crc_failures: 0,
                rejected: 0,
                rejected_speed: 0,
                rejected_span: 0,
                rejected_timestamp: 0,
                bytes_skipped: 0,
                bytes: 0,
            },
        }
    }

    /// Adds a byte to the frame being collected; returns true when 47 bytes
    /// are held. Bytes that cannot start a frame are skipped.
    fn push(&mut self, byte: u8) -> bool {
        match self.len {
            0 if byte != HEADER => {
                self.stats.bytes_skipped += 1;
                return false;
            }
            1 if byte != VER_LEN => {
                // Not a header after all; this byte may itself start one.
                self.stats.bytes_skipped += 1;
                self.len = 0;
                return self.push(byte);
            }
            _ => {}
        }
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = byte;
            self.len += 1;
        }
        self.len == FRAME_LEN
    }

    /// Decodes and checks the held frame.
    fn check(&mut self) -> Result<LidarFrame, bool> {
        let b = &self.buf;
        if crc8(b.get(..FRAME_LEN - 1).unwrap_or(&[])) != b[FRAME_LEN - 1] {
            self.stats.crc_failures += 1;
            return Err(true);
        }
        let speed = u16_at(b, 2);
        let start = u16_at(b, 4);
        let end = u16_at(b, 42);
        let ts = u16_at(b, 44);
        if !(MIN_SPEED_DPS..=MAX_SPEED_DPS).contains(&speed) {
            self.stats.rejected += 1;
            self.stats.rejected_speed += 1;
            return Err(false);
        }
        // Angles first: the span below needs both under 36000 (found by
        // the fuzzer: a start of 65535 underflowed the subtraction).
        if start >= 36000 || end >= 36000 {
            self.stats.rejected += 1;
            self.stats.rejected_span += 1;
            return Err(false);
        }
        let span = (end as u32 + 36000 - start as u32) % 36000;
        let max_span = speed as u32 * 100 * 11 / MIN_SAMPLE_RATE_HZ + 100;
        if span == 0 || span > max_span {
            self.stats.rejected += 1;
            self.stats.rejected_span += 1;
            return Err(false);
        }
        if ts >= TIMESTAMP_WRAP_MS {
            self.stats.rejected += 1;
            self.stats.rejected_timestamp += 1;
            return Err(false);
        }
        let mut f = LidarFrame {
            speed_dps: speed,
            start_cdeg: start,
            end_cdeg: end,
            timestamp_ms: ts,
            count: 12,
            points: [LidarPoint::default(); 12],
        };
        for (i, p) in f.points.iter_mut().enumerate() {
            let o = 6 + 3 * i;
            *p = LidarPoint {
                angle_cdeg: ((start as u32 + i as u32 * span / 11) % 36000) as u16,
                dist_mm: u16_at(b, o),
                intensity: b.get(o + 2).copied().unwrap_or(0),
            };
        }
        self.stats.frames += 1;
        Ok(f)
    }
}

impl LidarProtocol for Ld06 {
    fn feed(&mut self, byte: u8) -> Option<LidarFrame> {
        self.stats.bytes = self.stats.bytes.wrapping_add(1);
        if !self.push(byte) {
            return None;
        }
        match self.check() {
            Ok(f) => {
                self.len = 0;
                Some(f)
            }
            Err(_) => {
                // Resynchronise within the held bytes: drop the header and
                // re-feed the rest (46 bytes cannot complete a frame, so
                // nothing is emitted here).
                let held = self.buf;
                self.len = 0;
                self.stats.bytes_skipped += 1;
                for &b in held.iter().skip(1) {
                    let _ = self.push(b);
                }
                None
            }
        }
    }

    fn stats(&self) -> ParserStats {
        self.stats
    }
}

/// Encodes a frame (for the simulator and tests): 12 points, CRC added.
pub fn encode(
    speed_dps: u16,
    start_cdeg: u16,
    end_cdeg: u16,
    timestamp_ms: u16,
    points: &[(u16, u8); 12],
) -> [u8; FRAME_LEN] {
    let mut b = [0u8; FRAME_LEN];
    b[0] = HEADER;
    b[1] = VER_LEN;
    b[2..4].copy_from_slice(&speed_dps.to_le_bytes());
    b[4..6].copy_from_slice(&start_cdeg.to_le_bytes());
    for (chunk, (d, inten)) in b[6..42].chunks_exact_mut(3).zip(points) {
        if let [lo, hi, i] = chunk {
            [*lo, *hi] = d.to_le_bytes();
            *i = *inten;
        }
    }
    b[42..44].copy_from_slice(&end_cdeg.to_le_bytes());
    b[44..46].copy_from_slice(&timestamp_ms.to_le_bytes());
    b[46] = crc8(&b[..46]);
    b
}
