//! host-sim: the robovac core compiled for the host, with map loaders, a
//! CLI and benchmarks. The planning code is the firmware's own; this crate
//! only supplies files, big capacities and reports.

pub mod bench;
pub mod capacity;
pub mod drive;
pub mod floor;
pub mod maps;
pub mod metrics;
pub mod mission;
pub mod plan;
pub mod robot;
pub mod scen;
pub mod svg;
pub mod world;
