//! Integer math shared by every layer: angles (CORDIC), costs and square
//! roots, bitsets, and "keep the k smallest". A leaf: uses nothing else.

pub mod angle;
pub mod bits;
pub mod cost;
pub mod select;
