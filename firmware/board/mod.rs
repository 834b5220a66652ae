//! The board: the STM32F4's peripherals behind the core's traits (issue 11
//! §1). Only this module touches hardware; the core in `src/` never does.

#[cfg(not(feature = "pil"))]
pub mod clock;
#[cfg(feature = "pil")]
pub mod simlink;
