//! Division by a width fixed for a whole search, as a multiply and a shift
//! (Granlund and Montgomery, "Division by invariant integers using
//! multiplication", PLDI 1994).
//!
//! The search turns a linear cell index into (x, y) at every node it
//! expands. A hardware divide costs 20–40 cycles on an x86 core and up to
//! 12 on the Cortex-M4; a 32 × 32 → 64-bit multiply costs 3 and 1.
//!
//! With `m = ⌊2^40 / w⌋ + 1`, `m·w = 2^40 + e` with `0 < e ≤ w`, so
//! `i·m / 2^40 = i/w + i·e/(w·2^40)`. The added term is below `1/w`, and so
//! cannot carry `⌊i/w⌋` past the next integer, whenever `i·e < 2^40`: for
//! every `i < 2^24` and `w < 2^16`. Those bounds hold for every grid here
//! (widths are `u16`; the search asserts its capacity below 2^24 cells).

/// The largest index [`RowDivider::div`] divides exactly.
pub const EXACT_BELOW: usize = 1 << 24;

/// Divides indices below [`EXACT_BELOW`] by one width in `1..=65535`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowDivider {
    m: u64,
}

impl RowDivider {
    /// The divider for `width` (0 is taken as 1).
    pub const fn new(width: u16) -> Self {
        let w = if width == 0 { 1 } else { width as u64 };
        Self {
            m: (1u64 << 40) / w + 1,
        }
    }

    /// `⌊i / width⌋`, exact for `i <` [`EXACT_BELOW`].
    #[inline(always)]
    pub const fn div(self, i: u32) -> u32 {
        ((i as u64 * self.m) >> 40) as u32
    }
}
