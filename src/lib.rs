//! # robovac core
//!
//! The `#![no_std]`, allocation-free heart of the robot vacuum firmware.
//! Everything here is hardware-free and sized at compile time with const
//! generics, so the same code runs on the STM32F4 and in `host-sim`; time
//! is passed in, never read.
//!
//! ## The layers
//!
//! Each folder is a layer; a layer uses only the layers below it.
//!
//! ```text
//! mission   the executive: self-test, cover, edge, return, avoid, faults;
//!           `control` (100 Hz) and `plan` (10 Hz) entry points, events
//!    │
//! nav       configuration space, path follower, guard, DWA, edge pass,
//!    │      geometry                                  (seed 002 §3.1)
//!    │      localize  scan-to-map matching, fusion   (Hector SLAM)
//!    ├──────────────┐
//! coverage  │       robot     hal traits, odometry, wheel control,
//!  B-OHA*,  │                 LD06 lidar, evidence map
//!  BA*, …   │         │
//!    │      │         │
//! verify  metrics and the independent checker
//!    │
//! search    A*, OHA*, Theta*: one resumable loop     (seed 000 §2.3)
//!    │
//! grid      occupancy grid, line of sight, built-in maps
//!    │
//! math      angles, costs, bitsets, selection
//! ```
//!
//! - [`math`]: integer angles (CORDIC), costs and square roots, bitsets.
//! - [`grid`]: the bit-packed occupancy grid with covered/known layers,
//!   line of sight, built-in maps.
//! - [`search`]: A*, OHA* and Theta* behind one resumable, multi-goal,
//!   bounded best-first loop, and path pruning.
//! - [`verify`]: the metrics, defined once, and the independent checker.
//! - [`coverage`]: the online complete-coverage planners (B-OHA*, BA*,
//!   B-Theta*, our B-OHA*-PC) on one step loop and one bounded list.
//! - [`robot`]: hardware traits ([`robot::hal`]), odometry, wheel control,
//!   the LD06 parser and scan assembly, the evidence map.
//! - [`localize`]: scan-to-map matching (multi-resolution Gauss–Newton,
//!   correlative searches for the start and a kidnap) and its fusion with
//!   odometry.
//! - [`nav`]: configuration space, path follower, guard, DWA, edge pass.
//! - [`mission`]: the executive that runs a cleaning mission from sensor
//!   bytes to motor duties.
//! - `link` (feature `link`): the sim link's framed messages between
//!   host-sim and a firmware image in the emulator.
//! - [`capacity`]: the firmware's sizes, asserted at compile time.
//!
//! The algorithms follow the project's digest `ALGORITHMS.md` (seed 000 for
//! OHA*, pruning and B-OHA*, seed 004 for A*, seed 002 for DWA and path
//! following); each lives in a file named for it.
//!
//! No function in this crate panics on any input: off-map coordinates read as
//! blocked, capacities are checked and reported as typed errors.
#![no_std]
#![forbid(unsafe_code)]
#![deny(clippy::indexing_slicing)]
#![warn(missing_docs)]

pub mod capacity;
pub mod coverage;
pub mod grid;
#[cfg(feature = "link")]
pub mod link;
pub mod localize;
pub mod math;
pub mod mission;
pub mod nav;
pub mod robot;
pub mod search;
pub mod verify;

pub use grid::{Cell, Grid, GridError};
pub use search::{Algo, SearchError, SearchState, SearchStats};
