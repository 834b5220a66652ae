//! Integer math shared by every layer: angles (CORDIC), costs and square
//! roots, bitsets, division by an invariant width, and "keep the k smallest". A leaf: uses nothing else.

pub mod angle;
pub mod bits;
pub mod cost;
pub mod divide;
pub mod select;
