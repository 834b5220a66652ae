//! What the firmware logs about its mission (issue 11 §5), the same on the
//! robot and on the sim-link board: every event of the executive, and a
//! status line (state, pose, coverage by the robot's own count of planning
//! cells cleaned) every few seconds.

use robovac::capacity::FwPlanGrid;
use robovac::grid::Layer;
use robovac::mission::{Event, Mission};

/// A status line every 5 s of mission time.
pub const STATUS_US: u64 = 5_000_000;

/// One event as a log line.
pub fn event(e: &Event) {
    #[cfg(feature = "defmt")]
    defmt::info!("event: {}", e);
    #[cfg(not(feature = "defmt"))]
    defmt::info!("event: {}", defmt::Debug2Format(e));
}

/// The state, the pose and the coverage so far.
pub fn status(now_us: u64, m: &Mission, coarse: &FwPlanGrid) {
    let pose = m.pose();
    let covered = coarse.count(Layer::Covered);
    let free = coarse.free_cells();
    let pct_x10 = (covered * 1000).checked_div(free).unwrap_or(0);
    defmt::info!(
        "t {} s: {}; pose ({}, {}) mm {} mrad; covered {} of {} planning cells ({}.{} %)",
        now_us / 1_000_000,
        defmt::Debug2Format(&m.state()),
        pose.x_mm,
        pose.y_mm,
        pose.theta_mrad,
        covered,
        free,
        pct_x10 / 10,
        pct_x10 % 10
    );
}

/// A saved map that could not be loaded or saved, as a log line (the
/// robot's store; the sim-link board has none).
#[cfg(not(feature = "pil"))]
pub fn map_store(what: &str, e: &robovac::robot::map_image::MapImageError) {
    #[cfg(feature = "defmt")]
    defmt::warn!("{}: {}", what, e);
    #[cfg(not(feature = "defmt"))]
    defmt::warn!("{}: {}", what, defmt::Debug2Format(e));
}
