//! The board: the STM32F4's peripherals behind the core's traits (issue 11
//! §1). Only this module touches hardware; the core in `src/` never does.

#[cfg(not(feature = "pil"))]
pub mod battery;
#[cfg(not(feature = "pil"))]
pub mod bumper;
#[cfg(not(feature = "pil"))]
pub mod clock;
#[cfg(not(feature = "pil"))]
pub mod encoders;
#[cfg(not(feature = "pil"))]
pub mod flash_store;
#[cfg(not(feature = "pil"))]
pub mod lidar_dma;
#[cfg(feature = "pil")]
pub mod meter;
#[cfg(not(feature = "pil"))]
pub mod motors;
#[cfg(all(not(feature = "pil"), feature = "log-serial"))]
pub mod serial_log;
#[cfg(feature = "pil")]
pub mod simlink;
#[cfg(not(feature = "pil"))]
pub mod ticker;
#[cfg(not(feature = "pil"))]
pub mod watchdog;
#[cfg(not(feature = "pil"))]
pub mod wiring;
