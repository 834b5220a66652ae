//! Reporting: the host-side metrics helpers and the SVG pictures (one
//! canvas). Uses `io` and the run types it draws.

pub mod metrics;
pub mod mission;
pub mod svg;
