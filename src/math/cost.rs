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

/// Floor of the square root of `n`, exact for every `u32`.
///
/// Integer Newton (Heron) from a power of two at or above √n: the iterates
/// fall strictly to ⌊√n⌋, and the first one that does not fall is it. Each
/// step is one 32-bit division, a single `UDIV` on the Cortex-M4; five
/// steps at most for a 32-bit `n`.
pub const fn isqrt_u32(n: u32) -> u32 {
    if n < 2 {
        return n;
    }
    let bits = 32 - n.leading_zeros();
    let mut x = 1u32 << bits.div_ceil(2); // ≥ √n, ≤ 2^16
    loop {
        // x ≥ ⌊√n⌋ keeps n / x ≤ x + 2, so the sum stays below 2^18.
        // x ≥ 1 always; the checked form keeps a panic branch out of the
        // firmware.
        let q = match n.checked_div(x) {
            Some(q) => q,
            None => return 0,
        };
        let y = (x + q) >> 1;
        if y >= x {
            return x;
        }
        x = y;
    }
}

/// Euclidean distance between two points (mm), rounded down; exact for
/// any two `i32` points (the squares are summed in `u64`, saturating).
pub fn dist_mm(a: (i32, i32), b: (i32, i32)) -> i64 {
    let dx = (a.0 as i64 - b.0 as i64).unsigned_abs();
    let dy = (a.1 as i64 - b.1 as i64).unsigned_abs();
    isqrt_u64((dx * dx).saturating_add(dy * dy)) as i64
}

/// Floor of the square root of `n`, exact for every `u64`.
///
/// Issue 13's search speed: the bit-by-bit method took 32 rounds of 64-bit
/// arithmetic, most of the Euclidean heuristic's cost on the M4. Here `n`
/// is shifted by an even count until its top two bits are not both zero
/// (m = n·4^k ≥ 2^62); the root of m's high word gives its top 16 bits
/// x = hi·2^16 (hi ≥ 2^15); one Newton step from x gives the low 16 bits
/// with a single 32-bit division, since the remainder m − x² < 2^49 and
/// its Newton quotient r / 2x = δ + δ²/2x with δ²/2x < 1 (δ = √m − x < 2^16,
/// x ≥ 2^31). So x + ⌊r / 2x⌋ is ⌊√m⌋ or one more, and one test settles it.
/// ⌊√n⌋ = ⌊√m⌋ >> k.
pub const fn isqrt_u64(n: u64) -> u64 {
    if n <= u32::MAX as u64 {
        return isqrt_u32(n as u32) as u64;
    }
    let shift = n.leading_zeros() & !1;
    let m = n << shift;
    let hi = isqrt_u32((m >> 32) as u32);
    let x = (hi as u64) << 16;
    let r = m - x * x;
    let q = match ((r >> 17) as u32).checked_div(hi) {
        Some(q) => q as u64,
        None => return 0, // never: hi ≥ 2^15
    };
    let mut y = x + q;
    if y > u32::MAX as u64 || y * y > m {
        y -= 1;
    }
    y >> (shift / 2)
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
