//! The cleaning progress kept through a power loss (issue 12): which
//! planning cells are clean, stored after the map image
//! ([`super::map_image`]) in the same store, so that after a reset the
//! robot relocalises at its dock on the saved map and cleans only what is
//! left.
//!
//! Layout (little-endian), at the 4-byte boundary after the map image:
//!
//! | bytes | field |
//! |---|---|
//! | 0..4 | magic `RVPG` |
//! | 4..6 | version (1) |
//! | 6..8 | planning cell side, mm |
//! | 8..10 | width, cells |
//! | 10..12 | height, cells |
//! | 12..16 | CRC-32 (ISO-HDLC) of bytes 0..12 and the bits |
//! | 16.. | one bit a cell, row-major, least significant bit first: clean |
//!
//! The header is written last, so an image cut short by the power loss
//! it is meant for has no valid header and is refused whole.

use super::hal::Storage;
use super::map_image::{write_chunks, MapImageError};
use crate::grid::{Grid, Layer};

/// The image's first bytes.
pub const MAGIC: [u8; 4] = *b"RVPG";
/// The layout's version.
pub const VERSION: u16 = 1;
/// Header bytes before the bits.
pub const HEADER_BYTES: u32 = 16;

const CRC32: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// Where the progress image starts, after a map image of `map_bytes`.
pub fn offset_after(map_bytes: u32) -> u32 {
    map_bytes.div_ceil(4) * 4
}

/// Bytes of the image of `grid`.
pub fn bytes<const W: usize>(grid: &Grid<W>) -> u32 {
    HEADER_BYTES + (grid.width() * grid.height()).div_ceil(8)
}

/// An image (of whatever grid) starts at `offset` of `store`.
pub fn present(store: &mut (impl Storage + ?Sized), offset: u32) -> bool {
    let mut magic = [0u8; 4];
    store.read(offset, &mut magic).is_ok() && magic == MAGIC
}

/// Saves which cells of `grid` (planning cells of `cell_mm`) are clean,
/// as `clean(x, y)` says, at `offset` of `store` (erased bytes: the map
/// image's save erased them). Returns the bytes written.
pub fn save<const W: usize>(
    grid: &Grid<W>,
    cell_mm: u32,
    clean: impl Fn(i32, i32) -> bool,
    store: &mut (impl Storage + ?Sized),
    offset: u32,
) -> Result<u32, MapImageError> {
    let (w, h) = (grid.width(), grid.height());
    let n = bytes(grid) - HEADER_BYTES;
    let needed = offset.saturating_add(HEADER_BYTES + n);
    if needed > store.capacity() {
        return Err(MapImageError::TooLarge {
            needed,
            capacity: store.capacity(),
        });
    }
    let mut head = header(cell_mm, w, h);
    let mut crc = CRC32.digest();
    crc.update(head.get(..12).unwrap_or(&[]));
    let wide = w.max(1) as usize;
    write_chunks(store, offset + HEADER_BYTES, n, &mut crc, |byte| {
        (0..8).fold(0u8, |acc, bit| {
            let i = byte * 8 + bit;
            let (x, y) = (i % wide, i / wide);
            let on = y < h as usize && clean(x as i32, y as i32);
            acc | (u8::from(on) << bit)
        })
    })?;
    if let Some(c) = head.get_mut(12..16) {
        c.copy_from_slice(&crc.finalize().to_le_bytes());
    }
    store.write(offset, &head)?;
    Ok(HEADER_BYTES + n)
}

/// The header's bytes, the checksum left 0.
fn header(cell_mm: u32, w: u32, h: u32) -> [u8; 16] {
    let mut head = [0u8; 16];
    let fields = MAGIC
        .into_iter()
        .chain(VERSION.to_le_bytes())
        .chain((cell_mm as u16).to_le_bytes())
        .chain((w as u16).to_le_bytes())
        .chain((h as u16).to_le_bytes());
    for (slot, b) in head.iter_mut().zip(fields) {
        *slot = b;
    }
    head
}

/// Marks the clean cells of a saved image at `offset` in `grid`'s
/// covered layer (cells already marked stay). The image must be of a
/// grid of the same size and cell (the same saved map); otherwise, or on
/// any damage, nothing is marked. Returns the cells marked.
pub fn load<const W: usize>(
    grid: &mut Grid<W>,
    cell_mm: u32,
    store: &mut (impl Storage + ?Sized),
    offset: u32,
) -> Result<u32, MapImageError> {
    let mut head = [0u8; 16];
    store.read(offset, &mut head)?;
    let (w, h) = (grid.width(), grid.height());
    let mut want = header(cell_mm, w, h);
    if head.get(..4) != want.get(..4) {
        return Err(MapImageError::NoMap);
    }
    if head.get(4..6) != want.get(4..6) {
        let found = u16::from_le_bytes([head[4], head[5]]);
        return Err(MapImageError::Version { found });
    }
    if head.get(6..12) != want.get(6..12) {
        // Saved on a planning grid of another size: another map.
        return Err(MapImageError::Corrupt);
    }
    let n = (w * h).div_ceil(8);
    let mut crc = CRC32.digest();
    crc.update(want.get(..12).unwrap_or(&[]));
    let mut buf = [0u8; 64];
    for at in (0..n).step_by(64) {
        let chunk = buf.get_mut(..(n - at).min(64) as usize).unwrap_or(&mut []);
        store.read(offset + HEADER_BYTES + at, chunk)?;
        crc.update(chunk);
    }
    if let Some(c) = want.get_mut(12..16) {
        c.copy_from_slice(&crc.finalize().to_le_bytes());
    }
    if head != want {
        return Err(MapImageError::Corrupt);
    }
    let mut marked = 0;
    for at in (0..n).step_by(64) {
        let chunk = buf.get_mut(..(n - at).min(64) as usize).unwrap_or(&mut []);
        store.read(offset + HEADER_BYTES + at, chunk)?;
        for (k, b) in chunk.iter().enumerate() {
            for bit in 0..8 {
                let i = (at as usize + k) * 8 + bit;
                let (x, y) = ((i as u32 % w.max(1)) as i32, (i as u32 / w.max(1)) as i32);
                if b >> bit & 1 == 1 && grid.set(Layer::Covered, x, y, true).is_ok() {
                    marked += 1;
                }
            }
        }
    }
    Ok(marked)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::hal::StorageError;

    /// A small store in RAM.
    struct Ram([u8; 512]);

    impl Storage for Ram {
        fn capacity(&self) -> u32 {
            512
        }
        fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), StorageError> {
            let src = self.0.get(offset as usize..offset as usize + buf.len());
            buf.copy_from_slice(src.ok_or(StorageError::OutOfRange)?);
            Ok(())
        }
        fn erase(&mut self) -> Result<(), StorageError> {
            self.0 = [0xFF; 512];
            Ok(())
        }
        fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StorageError> {
            let dst = self
                .0
                .get_mut(offset as usize..offset as usize + data.len());
            dst.ok_or(StorageError::OutOfRange)?.copy_from_slice(data);
            Ok(())
        }
    }

    fn grid() -> Grid<4> {
        let mut g = Grid::new();
        g.reset(13, 7).unwrap();
        g
    }

    #[test]
    fn round_trip_marks_the_same_cells() {
        let mut store = Ram([0xFF; 512]);
        let g = grid();
        let clean = |x: i32, y: i32| (x * 3 + y * 5) % 4 == 0;
        let n = save(&g, 300, clean, &mut store, 40).unwrap();
        assert_eq!(n, bytes(&g));
        assert!(present(&mut store, 40) && !present(&mut store, 44));
        let mut back = grid();
        let marked = load(&mut back, 300, &mut store, 40).unwrap();
        let mut want = 0;
        for y in 0..7 {
            for x in 0..13 {
                assert_eq!(back.get(Layer::Covered, x, y), clean(x, y), "({x}, {y})");
                want += u32::from(clean(x, y));
            }
        }
        assert_eq!(marked, want);
    }

    #[test]
    fn damage_or_another_grid_is_refused_whole() {
        let mut store = Ram([0xFF; 512]);
        save(&grid(), 300, |_, _| true, &mut store, 0).unwrap();
        let mut other = Grid::<4>::new();
        other.reset(12, 7).unwrap();
        assert_eq!(
            load(&mut other, 300, &mut store, 0),
            Err(MapImageError::Corrupt)
        );
        let mut g = grid();
        assert_eq!(
            load(&mut g, 250, &mut store, 0),
            Err(MapImageError::Corrupt)
        );
        if let Some(b) = store.0.get_mut(HEADER_BYTES as usize + 3) {
            *b ^= 0x10;
        }
        assert_eq!(
            load(&mut g, 300, &mut store, 0),
            Err(MapImageError::Corrupt)
        );
        assert_eq!(
            g.count(Layer::Covered),
            0,
            "nothing marked from a damaged image"
        );
        let mut erased = Ram([0xFF; 512]);
        assert_eq!(load(&mut g, 300, &mut erased, 0), Err(MapImageError::NoMap));
        let mut small = Ram([0xFF; 512]);
        let big = {
            let mut b = Grid::<256>::new();
            b.reset(80, 80).unwrap();
            b
        };
        assert!(matches!(
            save(&big, 300, |_, _| true, &mut small, 0),
            Err(MapImageError::TooLarge { .. })
        ));
    }
}
