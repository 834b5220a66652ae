//! The robot's own I/O: the hardware traits, odometry, wheel control, the
//! lidar's wire protocol and the evidence map built from it. Uses `math`
//! and `grid`.

pub mod battery;
pub mod beam;
pub mod debounce;
pub mod hal;
pub mod lidar;
pub mod lidar_map;
pub mod map_image;
pub mod odometry;
pub mod progress_image;
pub mod wheel_control;
