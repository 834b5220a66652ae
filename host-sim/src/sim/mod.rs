//! The physical twin: the world with its people, the robot's motors,
//! encoders and lidar bytes, and the floor swept as truth. Uses `io`.

pub mod battery;
pub mod config;
pub mod floor;
pub mod hal;
pub mod objects;
pub mod robot;
pub mod scan;
pub mod world;
pub mod zones;
