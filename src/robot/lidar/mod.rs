//! Lidar input: wire protocols behind one small interface, and the scan
//! assembler that turns frames into revolutions stamped with the pose.
//!
//! A protocol is a byte-at-a-time parser ([`LidarProtocol`]) that yields
//! [`LidarFrame`]s of up to [`MAX_POINTS_PER_FRAME`] points with angles in
//! hundredths of a degree. LDROBOT's LD06/LD19/STL-19P protocol
//! ([`ld06`]) is the default; another family (the Neato XV-11 / Xiaomi LDS
//! 22-byte `0xFA` packets carry 4 points each) is added by implementing the
//! trait, without touching the assembler or the mapping.

pub mod ld06;
pub mod scan;

/// One measurement.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LidarPoint {
    /// Bearing in the lidar frame, 0.01° (0..36000), counter-clockwise
    /// from the robot's forward axis as the scan assembler reads it.
    pub angle_cdeg: u16,
    /// Range, mm (0 = no return).
    pub dist_mm: u16,
    /// Return strength.
    pub intensity: u8,
}

/// Most points one frame of any supported protocol carries.
pub const MAX_POINTS_PER_FRAME: usize = 12;

/// One decoded frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LidarFrame {
    /// Rotation speed, degrees per second.
    pub speed_dps: u16,
    /// Bearing of the first point, 0.01°.
    pub start_cdeg: u16,
    /// Bearing of the last point, 0.01°.
    pub end_cdeg: u16,
    /// Sensor timestamp, ms (LD06: wraps at 30 000).
    pub timestamp_ms: u16,
    /// Points used in `points`.
    pub count: u8,
    /// The points.
    pub points: [LidarPoint; MAX_POINTS_PER_FRAME],
}

impl LidarFrame {
    /// The frame's points.
    pub fn points(&self) -> &[LidarPoint] {
        self.points.get(..self.count as usize).unwrap_or(&[])
    }
}

/// What a parser dropped, and why.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ParserStats {
    /// Frames accepted.
    pub frames: u32,
    /// Frames whose checksum failed.
    pub crc_failures: u32,
    /// Frames with a good checksum but implausible content.
    pub rejected: u32,
    /// Of those: rotation speed out of range.
    pub rejected_speed: u32,
    /// Of those: angular span too wide for the speed, or an angle ≥ 360°.
    pub rejected_span: u32,
    /// Of those: a timestamp ≥ 30 000 ms (LD06 timestamps wrap there).
    pub rejected_timestamp: u32,
    /// Bytes skipped while looking for a frame start.
    pub bytes_skipped: u32,
    /// Bytes fed in total.
    pub bytes: u32,
}

/// A lidar wire protocol.
pub trait LidarProtocol {
    /// Feeds one byte; returns a frame when this byte completes a valid one.
    fn feed(&mut self, byte: u8) -> Option<LidarFrame>;
    /// Counters so far.
    fn stats(&self) -> ParserStats;
}
