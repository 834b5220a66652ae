//! The open list: an array-based 4-ary min-heap of fixed capacity, or, for
//! searches whose keys never fall below the last one popped, a bucket
//! queue in the same array ([`dial`], [`Order::Monotone`]).
//!
//! **Why 4-ary** (issue 13, search speed): a pop sifts down half as many
//! levels as in a binary heap, and the four children of a node sit side by
//! side in memory; a push sifts up half as many. The order is a strict
//! total order on the entries (below), so the entries come out in exactly
//! the order the binary heap gave: the search's results are unchanged.
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

pub mod dial;

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
    /// Smaller f first, then larger g, then smaller index. On a 64-bit
    /// host, f and g compare as one packed key (fewer branches); on the
    /// Cortex-M4, which has no 64-bit compare, in 32-bit steps. The order
    /// is the same.
    #[inline]
    #[cfg(target_pointer_width = "64")]
    fn before(&self, other: &Entry) -> bool {
        let key = |e: &Entry| ((e.f as u64) << 32) | (u32::MAX - e.g) as u64;
        let (a, b) = (key(self), key(other));
        a < b || (a == b && self.idx < other.idx)
    }

    #[inline]
    #[cfg(not(target_pointer_width = "64"))]
    fn before(&self, other: &Entry) -> bool {
        if self.f != other.f {
            return self.f < other.f;
        }
        if self.g != other.g {
            return self.g > other.g;
        }
        self.idx < other.idx
    }
}

/// Children per node.
const ARITY: usize = 4;

/// The open list was full.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Full;

/// How an [`OpenList`] orders its entries; chosen by [`OpenList::clear_for`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Order {
    /// The 4-ary heap: the strict total order of [`Entry`] (smaller f,
    /// then larger g, then smaller index). For any keys. Discriminant 0:
    /// an all-zero open list is an empty heap.
    Strict = 0,
    /// The dial ([`dial`]): smaller f first, equal f last in
    /// first out, g not kept. Only for keys that never fall below the last
    /// key popped (a consistent heuristic); a smaller key is raised to it.
    Monotone,
}

/// An open list of at most `CAP` entries: a 4-ary min-heap, or a dial over the same array ([`Order`]).
pub struct OpenList<const CAP: usize> {
    len: usize,
    items: [Entry; CAP],
    peak: usize,
    order: Order,
    dial: dial::Dial,
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
            order: Order::Strict,
            dial: dial::Dial::new(),
        }
    }

    /// Removes every entry (and resets the peak); the heap order.
    pub fn clear(&mut self) {
        self.clear_for(Order::Strict);
    }

    /// Removes every entry (and resets the peak) and takes `order` until
    /// the next clear.
    pub fn clear_for(&mut self, order: Order) {
        self.len = 0;
        self.peak = 0;
        self.order = order;
        self.dial = dial::Dial::new();
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
        match self.order {
            Order::Strict => self.peak,
            Order::Monotone => self.dial_peak(),
        }
    }

    /// Inserts an entry, or returns [`Full`].
    #[inline]
    pub fn push(&mut self, e: Entry) -> Result<(), Full> {
        match self.order {
            Order::Strict => self.heap_push(e),
            Order::Monotone => self.dial_push(e.f, e.idx),
        }
    }

    /// Removes and returns the first entry. In [`Order::Monotone`] its `g`
    /// reads 0 (the dial does not keep it).
    #[inline]
    pub fn pop(&mut self) -> Option<Entry> {
        match self.order {
            Order::Strict => self.heap_pop(),
            Order::Monotone => self.dial_pop(),
        }
    }

    fn heap_push(&mut self, e: Entry) -> Result<(), Full> {
        if self.len >= CAP {
            return Err(Full);
        }
        let mut i = self.len;
        self.len += 1;
        self.peak = self.peak.max(self.len);
        // Sift up: move parents down until `e` fits.
        while i > 0 {
            let p = (i - 1) / ARITY;
            match self.items.get(p) {
                Some(&pe) if e.before(&pe) => {
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

    fn heap_pop(&mut self) -> Option<Entry> {
        if self.len == 0 {
            return None;
        }
        let top = *self.items.first()?;
        self.len -= 1;
        let n = self.len;
        let last = *self.items.get(n)?;
        let mut i = 0usize;
        // Sift the former last entry down from the root.
        loop {
            let first = ARITY * i + 1;
            let Some((&head, rest)) = self
                .items
                .get(first..(first + ARITY).min(n))
                .and_then(|k| k.split_first())
            else {
                break;
            };
            let (mut c, mut ce) = (first, head);
            for (k, &e) in rest.iter().enumerate() {
                if e.before(&ce) {
                    (c, ce) = (first + 1 + k, e);
                }
            }
            if !ce.before(&last) {
                break;
            }
            if let Some(slot) = self.items.get_mut(i) {
                *slot = ce;
            }
            i = c;
        }
        if n > 0 {
            if let Some(slot) = self.items.get_mut(i) {
                *slot = last;
            }
        }
        Some(top)
    }
}
