//! Measuring and checking plans: the metrics defined once, and the
//! independent coverage checker. Uses `math` and `grid` only.

pub mod check;
pub mod metrics;
