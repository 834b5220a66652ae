//! A fixed-capacity bitset: one bit per cell, `NW` 32-bit words.
//!
//! The grid's layers and the search's closed/seen sets are all `Bits`.
//! Capacity is `NW * 32` bits; use [`words_for`] to size it.

/// Number of 32-bit words needed to hold `bits` bits.
pub const fn words_for(bits: usize) -> usize {
    bits.div_ceil(32)
}

/// A bitset of `NW * 32` bits, all stored inline.
#[derive(Clone, PartialEq, Eq)]
pub struct Bits<const NW: usize> {
    words: [u32; NW],
}

impl<const NW: usize> Default for Bits<NW> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const NW: usize> Bits<NW> {
    /// Number of bits this set can hold.
    pub const CAPACITY: usize = NW * 32;

    /// An empty set.
    pub const fn new() -> Self {
        Self { words: [0; NW] }
    }

    /// Reads bit `i`; bits beyond the capacity read as `false`.
    #[inline]
    pub fn get(&self, i: usize) -> bool {
        match self.words.get(i >> 5) {
            Some(w) => (w >> (i & 31)) & 1 != 0,
            None => false,
        }
    }

    /// Bits `i`, `i + 1` and `i + 2` as bits 0, 1 and 2 of the result (one
    /// or two word reads; bits beyond the capacity read `false`). The
    /// search reads a cell's three neighbours in a row with it.
    #[inline]
    pub fn get3(&self, i: usize) -> u32 {
        let (k, s) = (i >> 5, (i & 31) as u32);
        let lo = self.words.get(k).copied().unwrap_or(0) >> s;
        if s <= 29 {
            return lo & 0b111; // all three in one word (30 times in 32)
        }
        let hi = self.words.get(k + 1).copied().unwrap_or(0) << (32 - s);
        (lo | hi) & 0b111
    }

    /// Bits `i ..= i + 31` as bits 0..32 of the result; bits below 0 or
    /// beyond the capacity read `false`. Jump point search scans a row 32
    /// cells at a time with it ([`crate::search::jps`]).
    #[inline]
    pub fn window(&self, i: isize) -> u32 {
        if i <= -32 {
            return 0;
        }
        if i < 0 {
            return self.window(0) << i.unsigned_abs();
        }
        let (k, s) = ((i as usize) >> 5, (i & 31) as u32);
        let lo = self.words.get(k).copied().unwrap_or(0) as u64;
        let hi = self.words.get(k + 1).copied().unwrap_or(0) as u64;
        ((lo | hi << 32) >> s) as u32
    }

    /// The eight bits around bit `i` of a raster `w` bits wide, as bits
    /// 0..8 in the order E, NE, N, NW, W, SW, S, SE (y grows downward; the
    /// order of `search::NEIGHBOURS`): three reads of three bits, one per
    /// row (issue 13, search speed). Bit `i` is in column 0 when
    /// `left_edge`; its west side then reads 0. The caller masks what lies
    /// off the raster: the row above the first wraps to an index beyond the
    /// capacity and reads 0, but the east side of the last column reads the
    /// next row and the row below the last may read stale bits.
    #[inline(always)]
    pub fn ring(&self, i: usize, w: usize, left_edge: bool) -> u32 {
        /// (bit 0, bit 1, bit 2) of the row above to NW (3), N (2), NE (1).
        const ABOVE: [u32; 8] = [0, 8, 4, 12, 2, 10, 6, 14];
        // Bits x - 1 ..= x + 1 of the row whose bit x is r.
        let row = |r: usize| {
            if left_edge {
                self.get3(r) << 1 & 0b111
            } else {
                self.get3(r.wrapping_sub(1))
            }
        };
        let (a, m, b) = (row(i.wrapping_sub(w)), row(i), row(i.wrapping_add(w)));
        ABOVE.get(a as usize).copied().unwrap_or(0) | (m & 1) << 4 | (m >> 2) | b << 5
    }

    /// Sets bit `i` and returns whether it was set before (one word read
    /// and written: the search's close). Beyond the capacity: `true`,
    /// nothing changed.
    #[inline]
    pub fn test_and_set(&mut self, i: usize) -> bool {
        match self.words.get_mut(i >> 5) {
            Some(w) => {
                let m = 1u32 << (i & 31);
                let was = *w & m != 0;
                *w |= m;
                was
            }
            None => true,
        }
    }

    /// Sets bit `i` to `v`. Returns `false` (and changes nothing) when `i` is
    /// beyond the capacity.
    #[inline]
    pub fn put(&mut self, i: usize, v: bool) -> bool {
        match self.words.get_mut(i >> 5) {
            Some(w) => {
                let m = 1u32 << (i & 31);
                if v {
                    *w |= m
                } else {
                    *w &= !m
                }
                true
            }
            None => false,
        }
    }

    /// Sets bits `lo..hi` (a word at a time). Returns `false` (and changes
    /// nothing) when the range is empty or reaches beyond the capacity.
    pub fn set_range(&mut self, lo: usize, hi: usize) -> bool {
        if lo >= hi || hi > Self::CAPACITY {
            return false;
        }
        let (first, last) = (lo >> 5, (hi - 1) >> 5);
        for k in first..=last {
            let from = if k == first { lo & 31 } else { 0 };
            let to = if k == last { ((hi - 1) & 31) + 1 } else { 32 };
            let mask = (u32::MAX >> (32 - (to - from))) << from;
            if let Some(w) = self.words.get_mut(k) {
                *w |= mask;
            }
        }
        true
    }

    /// Clears the first `n` bits (rounded up to whole words), leaving the
    /// rest as they were. Searches use this to reset only the part of the
    /// set that the current map occupies.
    pub fn clear_prefix(&mut self, n: usize) {
        let w = words_for(n).min(NW);
        for word in self.words.iter_mut().take(w) {
            *word = 0;
        }
    }

    /// Clears every bit.
    pub fn clear_all(&mut self) {
        self.words = [0; NW];
    }

    /// Sets the first `n` bits and clears the rest.
    pub fn fill_prefix(&mut self, n: usize) {
        let n = n.min(Self::CAPACITY);
        for (k, word) in self.words.iter_mut().enumerate() {
            let lo = k * 32;
            *word = if lo + 32 <= n {
                u32::MAX
            } else if lo >= n {
                0
            } else {
                (1u32 << (n - lo)) - 1
            };
        }
    }

    /// Number of set bits among the first `n`.
    pub fn count_prefix(&self, n: usize) -> usize {
        let n = n.min(Self::CAPACITY);
        let mut total = 0usize;
        for (k, word) in self.words.iter().enumerate() {
            let lo = k * 32;
            if lo >= n {
                break;
            }
            let w = if lo + 32 <= n {
                *word
            } else {
                *word & ((1u32 << (n - lo)) - 1)
            };
            total += w.count_ones() as usize;
        }
        total
    }
}
