//! The sim link: framed, CRC-checked messages between host-sim and a
//! firmware image running in the emulator (processor-in-the-loop, issue
//! 11 §4). Only the sim-link board and host-sim use it; the real board
//! does not.
//!
//! **Frame.** A message is serialised with postcard, followed by its
//! CRC-16 (CRC-16/IBM-3740, little-endian), COBS-encoded, and ended by a
//! zero byte. A reader resynchronises at every zero byte: a corrupt or
//! overlong frame costs that frame only, and is counted.
//!
//! **Messages** ([`msg`]): the host sends the mission's configuration and
//! prior map, then one tick per control period (time, encoder counts, how
//! many lidar bytes it sent on the lidar UART for that period); the
//! firmware answers each tick with its motor command and state, sends the
//! executive's events as they happen, and a report at the end.

pub mod msg;

use crc::{Crc, CRC_16_IBM_3740};
use serde::{de::DeserializeOwned, Serialize};

/// Largest serialised message, bytes.
pub const MAX_MSG: usize = 512;
/// Largest frame on the wire (message, CRC, COBS overhead, the zero).
pub const MAX_FRAME: usize = cobs::max_encoding_length(MAX_MSG + 2) + 1;

const CRC16: Crc<u16> = Crc::<u16>::new(&CRC_16_IBM_3740);

/// What can go wrong on the link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkError {
    /// The message does not fit [`MAX_MSG`] (sending) or a frame overran
    /// the reader's buffer (receiving).
    TooLong,
    /// Bad COBS encoding.
    Framing,
    /// The CRC did not match.
    Crc,
    /// The bytes are not a message of the expected type.
    Decode,
}

impl LinkError {
    /// A short description.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::TooLong => "frame too long",
            Self::Framing => "bad COBS framing",
            Self::Crc => "CRC mismatch",
            Self::Decode => "not a message",
        }
    }
}

/// Encodes `msg` as one frame into `out`; returns the frame's length.
pub fn encode<T: Serialize>(msg: &T, out: &mut [u8]) -> Result<usize, LinkError> {
    let mut raw = [0u8; MAX_MSG + 2];
    let n = postcard::to_slice(msg, &mut raw)
        .map_err(|_| LinkError::TooLong)?
        .len();
    let crc = CRC16.checksum(raw.get(..n).unwrap_or(&[]));
    raw.get_mut(n..n + 2)
        .ok_or(LinkError::TooLong)?
        .copy_from_slice(&crc.to_le_bytes());
    let body = raw.get(..n + 2).unwrap_or(&[]);
    let m = cobs::try_encode(body, out).map_err(|_| LinkError::TooLong)?;
    *out.get_mut(m).ok_or(LinkError::TooLong)? = 0;
    Ok(m + 1)
}

/// Link error counts of a reader.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LinkStats {
    /// Frames decoded.
    pub frames: u32,
    /// Frames dropped: too long.
    pub too_long: u32,
    /// Frames dropped: bad COBS.
    pub framing: u32,
    /// Frames dropped: CRC mismatch.
    pub crc: u32,
    /// Frames dropped: not a message.
    pub decode: u32,
}

/// Reassembles frames from bytes, `N` bytes of buffer (at least
/// [`MAX_FRAME`] for every message to fit).
pub struct FrameReader<const N: usize> {
    buf: [u8; N],
    len: usize,
    overflow: bool,
    stats: LinkStats,
}

impl<const N: usize> Default for FrameReader<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> FrameReader<N> {
    /// An empty reader.
    pub const fn new() -> Self {
        Self {
            buf: [0; N],
            len: 0,
            overflow: false,
            stats: LinkStats {
                frames: 0,
                too_long: 0,
                framing: 0,
                crc: 0,
                decode: 0,
            },
        }
    }

    /// What was decoded and dropped so far.
    pub fn stats(&self) -> LinkStats {
        self.stats
    }

    /// Feeds one byte; at a frame's end, its message or why it was dropped
    /// (the error is also counted).
    pub fn push<T: DeserializeOwned>(&mut self, byte: u8) -> Option<Result<T, LinkError>> {
        if byte != 0 {
            match self.buf.get_mut(self.len) {
                Some(b) => {
                    *b = byte;
                    self.len += 1;
                }
                None => self.overflow = true,
            }
            return None;
        }
        let (len, overflow) = (self.len, self.overflow);
        self.len = 0;
        self.overflow = false;
        if len == 0 && !overflow {
            return None; // an empty frame: a resynchronising zero
        }
        let r = if overflow {
            Err(LinkError::TooLong)
        } else {
            self.decode(len)
        };
        self.count(&r);
        Some(r)
    }

    fn decode<T: DeserializeOwned>(&mut self, len: usize) -> Result<T, LinkError> {
        let frame = self.buf.get_mut(..len).ok_or(LinkError::TooLong)?;
        let n = cobs_decode_in_place(frame).ok_or(LinkError::Framing)?;
        let body = frame.get(..n).ok_or(LinkError::Framing)?;
        let split = n.checked_sub(2).ok_or(LinkError::Crc)?;
        let (msg, crc) = body.split_at(split);
        let got = u16::from_le_bytes([
            crc.first().copied().unwrap_or(0),
            crc.get(1).copied().unwrap_or(0),
        ]);
        if CRC16.checksum(msg) != got {
            return Err(LinkError::Crc);
        }
        postcard::from_bytes(msg).map_err(|_| LinkError::Decode)
    }

    fn count<T>(&mut self, r: &Result<T, LinkError>) {
        let s = &mut self.stats;
        let c = match r {
            Ok(_) => &mut s.frames,
            Err(LinkError::TooLong) => &mut s.too_long,
            Err(LinkError::Framing) => &mut s.framing,
            Err(LinkError::Crc) => &mut s.crc,
            Err(LinkError::Decode) => &mut s.decode,
        };
        *c = c.wrapping_add(1);
    }
}

/// COBS decoding in place (a frame without its zero delimiter); None for a
/// malformed frame. Written here rather than taken from the cobs crate
/// (which encodes for us): its decoder indexes with bounds checks the
/// compiler cannot remove, two panicking branches in the firmware image
/// (issue 11 §6). The output never overtakes the input, so in place is
/// safe.
fn cobs_decode_in_place(buf: &mut [u8]) -> Option<usize> {
    let (mut src, mut dst) = (0usize, 0usize);
    while src < buf.len() {
        let code = *buf.get(src)?;
        if code == 0 {
            return None;
        }
        src += 1;
        for _ in 1..code {
            let b = *buf.get(src)?;
            *buf.get_mut(dst)? = b;
            src += 1;
            dst += 1;
        }
        if code != 0xFF && src < buf.len() {
            *buf.get_mut(dst)? = 0;
            dst += 1;
        }
    }
    Some(dst)
}
