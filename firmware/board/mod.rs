//! The board: the STM32F4's peripherals behind the core's traits (issue 11
//! §1). Only this module touches hardware; the core in `src/` never does.

pub mod clock;
