//! The open list: an array-based binary min-heap of fixed capacity.
//!
//! **Lazy deletion** (our choice, ALGORITHMS.md leaves it to us): when a
//! cell's cost improves, a new entry is pushed and the old one stays in the
//! heap; when an entry is popped for a cell that is already closed, the
//! search skips it. This needs no per-cell heap-position array (which would
//! cost 4 bytes a cell of RAM), at the price of a few duplicate entries. The
//! capacity is a separate const generic because the open list holds a
//! frontier, far smaller than the map; when it is full, `push` returns
//! [`Full`] and the search reports `OpenListFull` instead of losing a node.
//!
//! Ordering: smallest `f` first; among equal `f`, largest `g` first (the
//! entry nearer the goal), then smallest cell index, so runs are
//! deterministic.

/// A heap entry: priority `f`, cost-so-far `g`, and the cell's index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Entry {
    /// f = g + h, in cost units.
    pub f: u32,
    /// g, in cost units.
    pub g: u32,
    /// Linear cell index.
    pub idx: u32,
}

impl Entry {
    #[inline]
    fn before(&self, other: &Entry) -> bool {
        (self.f, u32::MAX - self.g, self.idx) < (other.f, u32::MAX - other.g, other.idx)
    }
}

/// The open list was full.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Full;

/// A binary min-heap of at most `CAP` entries.
pub struct OpenList<const CAP: usize> {
    len: usize,
    items: [Entry; CAP],
    peak: usize,
}

impl<const CAP: usize> Default for OpenList<CAP> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const CAP: usize> OpenList<CAP> {
    /// An empty list.
    pub const fn new() -> Self {
        Self {
            len: 0,
            items: [Entry { f: 0, g: 0, idx: 0 }; CAP],
            peak: 0,
        }
    }

    /// Removes every entry (and resets the peak).
    pub fn clear(&mut self) {
        self.len = 0;
        self.peak = 0;
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Largest number of entries held since the last `clear`.
    pub fn peak(&self) -> usize {
        self.peak
    }

    /// Inserts an entry, or returns [`Full`].
    pub fn push(&mut self, e: Entry) -> Result<(), Full> {
        if self.len >= CAP {
            return Err(Full);
        }
        let mut i = self.len;
        self.len += 1;
        self.peak = self.peak.max(self.len);
        // Sift up.
        while i > 0 {
            let p = (i - 1) / 2;
            match self.items.get(p) {
                Some(pe) if e.before(pe) => {
                    let pe = *pe;
                    if let Some(slot) = self.items.get_mut(i) {
                        *slot = pe;
                    }
                    i = p;
                }
                _ => break,
            }
        }
        if let Some(slot) = self.items.get_mut(i) {
            *slot = e;
        }
        Ok(())
    }

    /// Removes and returns the first entry.
    pub fn pop(&mut self) -> Option<Entry> {
        if self.len == 0 {
            return None;
        }
        let top = *self.items.first()?;
        self.len -= 1;
        let last = *self.items.get(self.len)?;
        let n = self.len;
        let mut i = 0usize;
        // Sift the former last entry down from the root.
        loop {
            let l = 2 * i + 1;
            if l >= n {
                break;
            }
            let r = l + 1;
            let mut c = l;
            if r < n {
                if let (Some(re), Some(le)) = (self.items.get(r), self.items.get(l)) {
                    if re.before(le) {
                        c = r;
                    }
                }
            }
            let ce = *self.items.get(c)?;
            if ce.before(&last) {
                if let Some(slot) = self.items.get_mut(i) {
                    *slot = ce;
                }
                i = c;
            } else {
                break;
            }
        }
        if n > 0 {
            if let Some(slot) = self.items.get_mut(i) {
                *slot = last;
            }
        }
        Some(top)
    }
}
