//! The map kept between runs (issue 12): a first run in unknown mode
//! explores and cleans, then saves its evidence map and the dock's pose
//! on it; the next run loads them, relocalises at the dock and cleans in
//! known mode, as real robot vacuums are used.
//!
//! The image is a 32-byte header and the map's cells as they are held
//! (two 4-bit counters a byte: 28.8 KB for a 12 × 12 m home at 5 cm, in
//! one 128 KB flash sector of the F411), on any [`Storage`]. Little-endian
//! header:
//!
//! | bytes | field |
//! |---|---|
//! | 0–3 | magic `RVMP` |
//! | 4–5 | format version ([`VERSION`]) |
//! | 6–7 | cell side, mm |
//! | 8–11 | width, height, cells |
//! | 12–23 | the dock: x, y mm, heading mrad |
//! | 24–27 | bytes of cells that follow |
//! | 28–31 | CRC-32 (ISO-HDLC) of bytes 0–27 and the cells |
//!
//! The saved map keeps the walls, not the people (`kept`): weak and lone
//! hits are saved as unknown. The next run starts from it in mapping mode
//! ([`crate::mission::MissionConfig::prior_saved`]).
//!
//! The header is written last, after the cells: a save cut short by a
//! power loss leaves an erased header, read as "no map" rather than as a
//! half-written one. A map that fails its checks is refused whole and the
//! evidence map is left empty: a robot that loaded half a map would
//! localise against walls that are not there.

use crate::robot::hal::{Storage, StorageError};
use crate::robot::lidar_map::{EvidenceMap, LIMIT, OCCUPIED_AT, PRIOR_WALL};
use crate::robot::odometry::Pose;
use crc::{Crc, CRC_32_ISO_HDLC};

/// The image's first four bytes.
pub const MAGIC: [u8; 4] = *b"RVMP";
/// The format written; a different one is refused.
pub const VERSION: u16 = 1;
/// Header bytes before the cells.
pub const HEADER_BYTES: u32 = 32;

const CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// Why a map could not be saved or loaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MapImageError {
    /// The store failed.
    Storage(StorageError),
    /// No map saved (an erased store, or something else in it).
    NoMap,
    /// A map in another format.
    Version {
        /// The version found.
        found: u16,
    },
    /// The map is larger than this build's evidence map, or the store.
    TooLarge {
        /// Bytes the image needs.
        needed: u32,
        /// Bytes there are.
        capacity: u32,
    },
    /// The sizes disagree or the checksum fails: the map is refused.
    Corrupt,
}

impl From<StorageError> for MapImageError {
    fn from(e: StorageError) -> Self {
        MapImageError::Storage(e)
    }
}

impl core::fmt::Display for MapImageError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            MapImageError::Storage(e) => write!(f, "the map store failed: {e:?}"),
            MapImageError::NoMap => write!(f, "no saved map"),
            MapImageError::Version { found } => {
                write!(
                    f,
                    "a saved map of format {found}, this build reads {VERSION}"
                )
            }
            MapImageError::TooLarge { needed, capacity } => {
                write!(f, "the map needs {needed} bytes, there are {capacity}")
            }
            MapImageError::Corrupt => write!(f, "the saved map is corrupt (sizes or checksum)"),
        }
    }
}

/// Saves `map` and the `dock` pose on it to `store` (erased first).
/// Returns the bytes written.
pub fn save<const B: usize>(
    map: &EvidenceMap<B>,
    dock: Pose,
    store: &mut (impl Storage + ?Sized),
) -> Result<u32, MapImageError> {
    let cells = map.cell_bytes();
    let n = cells.len() as u32;
    let needed = HEADER_BYTES + n;
    if needed > store.capacity() {
        return Err(MapImageError::TooLarge {
            needed,
            capacity: store.capacity(),
        });
    }
    let mut head = header(map, dock, n);
    let mut crc = CRC32.digest();
    crc.update(head.get(..28).unwrap_or(&[]));
    store.erase()?;
    // The cells kept, a chunk at a time (the live map is left as it is).
    write_chunks(store, HEADER_BYTES, n, &mut crc, |i| {
        nibble(kept(map, 2 * i)) | (nibble(kept(map, 2 * i + 1)) << 4)
    })?;
    if let Some(c) = head.get_mut(28..32) {
        c.copy_from_slice(&crc.finalize().to_le_bytes());
    }
    store.write(0, &head)?;
    Ok(needed)
}

/// Writes `n` bytes at `offset` of `store`, byte `i` being `byte(i)`, a
/// 64-byte chunk at a time, each into `crc` as well (the images' bodies).
pub(crate) fn write_chunks(
    store: &mut (impl Storage + ?Sized),
    offset: u32,
    n: u32,
    crc: &mut crc::Digest<'_, u32>,
    byte: impl Fn(usize) -> u8,
) -> Result<(), StorageError> {
    let mut buf = [0u8; 64];
    let mut at = 0u32;
    while at < n {
        let len = (n - at).min(buf.len() as u32) as usize;
        let chunk = buf.get_mut(..len).unwrap_or(&mut []);
        for (k, b) in chunk.iter_mut().enumerate() {
            *b = byte(at as usize + k);
        }
        crc.update(chunk);
        store.write(offset + at, chunk)?;
        at += len as u32;
    }
    Ok(())
}

/// A counter as its stored nibble.
fn nibble(v: i8) -> u8 {
    (v as u8) & 0x0F
}

/// What the saved map keeps of cell `i` (row-major; past the map: 0).
/// It keeps the walls, not the people: an occupied cell is kept only at
/// full evidence ([`LIMIT`]) with at least two such neighbours (a piece of
/// wall), or as a bump's mark ([`PRIOR_WALL`]); weaker or lone hits (a
/// person's trail the beams had not yet wiped, range noise) are saved as
/// unknown, for the next run to see again. Kept as walls, such hits closed
/// doorways at the next run's start (on the l10su home, seeds 2–4: 86 %,
/// 61 % failing its way home, 94 %; with this rule 96 %, 94 %, 97 %).
fn kept<const B: usize>(map: &EvidenceMap<B>, i: usize) -> i8 {
    let w = map.width().max(1) as usize;
    let (cx, cy) = ((i % w) as i32, (i / w) as i32);
    if cy >= map.height() as i32 {
        return 0;
    }
    let e = map.evidence(cx, cy);
    if e < OCCUPIED_AT || e == PRIOR_WALL {
        return e;
    }
    let strong = |x: i32, y: i32| map.evidence(x, y) >= LIMIT;
    let around = (-1..=1)
        .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
        .filter(|&(dx, dy)| (dx, dy) != (0, 0) && strong(cx + dx, cy + dy))
        .count();
    if e >= LIMIT && around >= 2 {
        e
    } else {
        0
    }
}

/// The header's bytes, the checksum left 0.
fn header<const B: usize>(map: &EvidenceMap<B>, dock: Pose, n: u32) -> [u8; 32] {
    let mut h = [0u8; 32];
    let fields = MAGIC
        .into_iter()
        .chain(VERSION.to_le_bytes())
        .chain((map.res_mm() as u16).to_le_bytes())
        .chain((map.width() as u16).to_le_bytes())
        .chain((map.height() as u16).to_le_bytes())
        .chain(dock.x_mm.to_le_bytes())
        .chain(dock.y_mm.to_le_bytes())
        .chain(dock.theta_mrad.to_le_bytes())
        .chain(n.to_le_bytes());
    for (slot, b) in h.iter_mut().zip(fields) {
        *slot = b;
    }
    h
}

/// The little-endian `N` bytes of `h` at `i` (zeros past its end).
fn le<const N: usize>(h: &[u8], i: usize) -> [u8; N] {
    let mut a = [0u8; N];
    if let Some(src) = h.get(i..i + N) {
        a.copy_from_slice(src);
    }
    a
}

/// Loads a saved map into `map` (sized from the image) and returns the
/// dock's pose on it. On any error the map is left empty (0 × 0).
pub fn load<const B: usize>(
    store: &mut (impl Storage + ?Sized),
    map: &mut EvidenceMap<B>,
) -> Result<Pose, MapImageError> {
    let r = load_checked(store, map);
    if r.is_err() {
        map.clear();
    }
    r
}

fn load_checked<const B: usize>(
    store: &mut (impl Storage + ?Sized),
    map: &mut EvidenceMap<B>,
) -> Result<Pose, MapImageError> {
    let mut h = [0u8; 32];
    store.read(0, &mut h)?;
    let u16_at = |i: usize| u16::from_le_bytes(le(&h, i));
    let u32_at = |i: usize| u32::from_le_bytes(le(&h, i));
    if le::<4>(&h, 0) != MAGIC {
        return Err(MapImageError::NoMap);
    }
    if u16_at(4) != VERSION {
        return Err(MapImageError::Version { found: u16_at(4) });
    }
    let (res, w, ht) = (u16_at(6) as u32, u16_at(8) as u32, u16_at(10) as u32);
    let n = u32_at(24);
    let sized = w > 0 && ht > 0 && res > 0 && n == (w * ht).div_ceil(2);
    if !sized || HEADER_BYTES.saturating_add(n) > store.capacity() {
        return Err(MapImageError::Corrupt);
    }
    map.reset(w, ht, res).map_err(|_| MapImageError::TooLarge {
        needed: n,
        capacity: B as u32,
    })?;
    store.read(HEADER_BYTES, map.cell_bytes_mut())?;
    let mut crc = CRC32.digest();
    crc.update(h.get(..28).unwrap_or(&[]));
    crc.update(map.cell_bytes());
    if crc.finalize() != u32_at(28) {
        return Err(MapImageError::Corrupt);
    }
    Ok(Pose {
        x_mm: u32_at(12) as i32,
        y_mm: u32_at(16) as i32,
        theta_mrad: u32_at(20) as i32,
    })
}
