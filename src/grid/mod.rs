//! The map as the planners see it: the bit-packed occupancy grid with its
//! covered and known layers, line of sight, and the built-in maps.
//! Uses `math` only.

pub mod los;
pub mod maps;
pub mod occupancy;
pub mod rooms;
pub mod shift;
pub mod zones;

pub use occupancy::{Cell, Grid, GridError, Layer};
pub use zones::{Zone, ZoneError, Zones};
