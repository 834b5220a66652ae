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
        let k = i >> 5;
        let lo = self.words.get(k).copied().unwrap_or(0) as u64;
        let hi = self.words.get(k + 1).copied().unwrap_or(0) as u64;
        (((hi << 32 | lo) >> (i & 31)) & 0b111) as u32
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
