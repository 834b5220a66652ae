//! The robot's non-volatile store on the host: the core's [`Storage`] as
//! bytes in memory, kept in a file between runs (on the chip it is a flash
//! sector). Sized as that sector, so a map too large for the robot is too
//! large here.

use std::path::Path;

use robovac::robot::hal::{Storage, StorageError};

/// Bytes of the store: one 128 KiB flash sector, as on the F411.
pub const STORE_BYTES: usize = 128 * 1024;

/// A store of [`STORE_BYTES`] in memory.
#[derive(Clone, Debug)]
pub struct MemStore {
    bytes: Vec<u8>,
    /// One past the last byte written (what a file keeps).
    used: usize,
}

impl Default for MemStore {
    fn default() -> Self {
        Self::erased()
    }
}

impl MemStore {
    /// An erased store (every byte 0xFF).
    pub fn erased() -> Self {
        Self {
            bytes: vec![0xFF; STORE_BYTES],
            used: 0,
        }
    }

    /// The store as a file left it (erased beyond the file's bytes).
    pub fn from_file(path: &Path) -> Result<Self, String> {
        let data = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        if data.len() > STORE_BYTES {
            return Err(format!(
                "{}: {} bytes, more than the robot's store of {STORE_BYTES}",
                path.display(),
                data.len()
            ));
        }
        let mut s = Self::erased();
        s.bytes[..data.len()].copy_from_slice(&data);
        s.used = data.len();
        Ok(s)
    }

    /// The bytes written, as a file keeps them.
    pub fn written(&self) -> &[u8] {
        &self.bytes[..self.used]
    }

    /// The store's bytes (for tests that damage them).
    pub fn bytes_mut(&mut self) -> &mut [u8] {
        &mut self.bytes
    }

    fn range(&self, offset: u32, len: usize) -> Result<std::ops::Range<usize>, StorageError> {
        let start = offset as usize;
        let end = start.checked_add(len).ok_or(StorageError::OutOfRange)?;
        (end <= self.bytes.len())
            .then_some(start..end)
            .ok_or(StorageError::OutOfRange)
    }
}

impl Storage for MemStore {
    fn capacity(&self) -> u32 {
        self.bytes.len() as u32
    }

    fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), StorageError> {
        let r = self.range(offset, buf.len())?;
        buf.copy_from_slice(&self.bytes[r]);
        Ok(())
    }

    fn erase(&mut self) -> Result<(), StorageError> {
        self.bytes.fill(0xFF);
        self.used = 0;
        Ok(())
    }

    /// As flash: a write can only clear bits of erased bytes.
    fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StorageError> {
        let r = self.range(offset, data.len())?;
        self.used = self.used.max(r.end);
        for (b, d) in self.bytes[r].iter_mut().zip(data) {
            *b &= d;
        }
        Ok(())
    }
}
