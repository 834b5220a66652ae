//! Integer path costs and distances.
//!
//! Costs are unsigned fixed-point numbers in units of `1 / COST_PER_CELL`
//! of a cell side. `COST_PER_CELL = 5741` and `COST_DIAGONAL = 8119` are a
//! convergent of the continued fraction of √2 (8119/5741 = 1.41421355…,
//! error 1.1·10⁻⁸), so an integer octile cost differs from the true
//! `straight + √2·diagonal` by under 10⁻⁷ cells on any path up to 10⁴
//! diagonal steps. That keeps integer A* optimal against MovingAI's
//! floating-point optima (tolerance 10⁻³) while staying in `u32`: a path of
//! up to 748 000 cells fits (u32::MAX / 5741). Sums saturate rather than wrap.

/// Cost of one straight (4-connected) step: one cell side.
pub const COST_PER_CELL: u32 = 5741;
/// Cost of one diagonal step: √2 cell sides, to 1.1·10⁻⁸ relative error.
pub const COST_DIAGONAL: u32 = 8119;

/// Floor of the square root of `n`, exact for every `u64`.
pub const fn isqrt_u64(n: u64) -> u64 {
    if n < 2 {
        return n;
    }
    // Bit-by-bit method: no division, constant 32 iterations, exact.
    let mut rem = n;
    let mut root = 0u64;
    // Highest power of four not above n.
    let mut bit = 1u64 << ((63 - n.leading_zeros()) & !1);
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// Square root of `n` rounded to the nearest integer.
pub const fn isqrt_round_u64(n: u64) -> u64 {
    let r = isqrt_u64(n);
    // (r + 0.5)² = r² + r + 0.25, so round up when n - r² > r.
    if n - r * r > r {
        r + 1
    } else {
        r
    }
}

/// Euclidean distance of the vector (dx, dy) cells, in cost units, rounded.
#[inline]
pub fn euclid(dx: i32, dy: i32) -> u32 {
    let dx = dx.unsigned_abs() as u64;
    let dy = dy.unsigned_abs() as u64;
    let c = COST_PER_CELL as u64;
    let d = isqrt_round_u64((dx * dx + dy * dy) * c * c);
    if d > u32::MAX as u64 {
        u32::MAX
    } else {
        d as u32
    }
}

/// Octile distance (8-connected shortest path on an empty grid), in cost units.
#[inline]
pub fn octile(dx: i32, dy: i32) -> u32 {
    let dx = dx.unsigned_abs();
    let dy = dy.unsigned_abs();
    let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
    lo.saturating_mul(COST_DIAGONAL)
        .saturating_add((hi - lo).saturating_mul(COST_PER_CELL))
}

/// Converts a cost to cells (for reporting only; never used in a hot loop).
pub fn to_cells(cost: u32) -> f32 {
    cost as f32 / COST_PER_CELL as f32
}
