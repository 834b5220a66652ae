//! host-sim: the robovac core compiled for the host, with map loaders, a
//! physical twin, a CLI and benchmarks. The planning code is the firmware's
//! own; this crate only supplies files, big capacities, physics and
//! reports.
//!
//! - [`capacity`]: every host size in one place.
//! - [`io`]: map loaders and scenarios.
//! - [`sim`]: the twin (world, robot, floor truth).
//! - [`run`]: plans, drives, missions, benchmark suites.
//! - [`report`]: metrics helpers and SVG pictures.
//!
//! The command line (`src/main.rs`, `src/cli/`) is one file per command
//! on top of these.

pub mod capacity;
pub mod io;
pub mod report;
pub mod run;
pub mod sim;
