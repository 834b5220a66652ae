//! Running the core: coverage plans, drives, missions and the benchmark
//! suites, measured. Uses `io`, `sim`, `report` and `capacity`.

pub mod bench;
pub mod coverage_bench;
pub mod dock;
pub mod drive;
pub mod engines;
pub mod executive;
pub mod inject;
pub mod measure;
pub mod mission;
pub mod mission_debug;
pub mod mission_map;
pub mod parts;
pub mod peers;
pub mod pil;
pub mod plan;
pub mod power;
pub mod power_loss;
pub mod replan;
mod report_json;
pub mod rooms;
pub mod seeds;
pub mod suite;
pub mod way_home;
