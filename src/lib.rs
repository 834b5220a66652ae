//! # robovac core
//!
//! The `#![no_std]`, allocation-free heart of the robot vacuum firmware: a
//! bit-packed occupancy grid, fixed-capacity path search (A*, OHA*, Theta*,
//! multi-goal), and path pruning. Everything here is hardware-free and sized
//! at compile time with const generics, so the same code runs on the STM32F4
//! and in `host-sim`.
//!
//! The algorithms follow the project's digest `ALGORITHMS.md` (seed 000 for
//! OHA*, pruning and B-OHA*, seed 004 for A*, seed 002 for DWA and path
//! following). Each algorithm lives in a file named for it; the machinery
//! they share (grid, open list, line of sight, costs, the search loop,
//! configuration space) is written once.
//!
//! The robot side: hardware traits ([`hal`]), odometry, wheel control, the
//! LD06 lidar parser and scan assembly, the evidence map, and the mission
//! executive ([`mission`]) that runs a cleaning mission from sensor bytes
//! to motor duties, with time passed in.
//!
//! No function in this crate panics on any input: off-map coordinates read as
//! blocked, capacities are checked and reported as typed errors.
#![no_std]
#![forbid(unsafe_code)]
#![deny(clippy::indexing_slicing)]
#![warn(missing_docs)]

pub mod angle;
pub mod astar;
pub mod b_oha;
pub mod b_oha_pc;
pub mod b_theta;
pub mod ba_star;
pub mod bits;
pub mod capacity;
pub mod check;
pub mod cost;
pub mod coverage;
pub mod cspace;
pub mod dwa;
pub mod edge;
pub mod follow;
pub mod grid;
pub mod guard;
pub mod hal;
pub mod lidar;
pub mod lidar_map;
pub mod los;
pub mod maps;
pub mod metrics;
pub mod mission;
pub mod odometry;
pub mod oha;
pub mod open_list;
pub mod prune;
pub mod search;
pub mod select;
pub mod theta_star;
pub mod wheel_control;

pub use grid::{Cell, Grid, GridError};
pub use search::{Algo, SearchError, SearchState, SearchStats};
