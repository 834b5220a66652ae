//! The twin behind the core's hardware traits ([`robovac::robot::hal`]):
//! motors, encoders, bumper, the lidar's UART and the clock, as the STM32
//! board implements them on the robot.

use robovac::robot::hal::{
    Bumper, BumperSwitches, ByteSource, Clock, MotorDriver, QuadratureEncoder,
};

use super::robot::Sim;

impl BumperSwitches for Sim {
    /// Closed when a switch closed at any physics step since the last read
    /// (a press shorter than a control period is not lost).
    fn read_bumper(&mut self) -> Bumper {
        std::mem::take(&mut self.bumper)
    }
}

impl MotorDriver for Sim {
    fn set_duty(&mut self, left_pm: i16, right_pm: i16) {
        self.braking = false;
        self.duty = [
            left_pm.clamp(-1000, 1000) as f64 / 1000.0,
            right_pm.clamp(-1000, 1000) as f64 / 1000.0,
        ];
    }
    fn brake(&mut self) {
        self.braking = true;
        self.duty = [0.0; 2];
    }
    fn coast(&mut self) {
        self.braking = false;
        self.duty = [0.0; 2];
    }
}

/// One wheel's encoder, read through the core's trait.
pub struct SimEncoder<'a> {
    /// The robot.
    pub sim: &'a Sim,
    /// 0 left, 1 right.
    pub wheel: usize,
}

impl QuadratureEncoder for SimEncoder<'_> {
    fn count(&mut self) -> u16 {
        self.sim.encoder(self.wheel)
    }
}

impl Sim {
    /// Both encoders' counts (left, right), read through the core's trait.
    pub fn read_encoders(&self) -> (u16, u16) {
        let l = SimEncoder {
            sim: self,
            wheel: 0,
        }
        .count();
        let r = SimEncoder {
            sim: self,
            wheel: 1,
        }
        .count();
        (l, r)
    }
}

impl ByteSource for Sim {
    fn read(&mut self, buf: &mut [u8]) -> usize {
        let mut n = 0;
        while n < buf.len() {
            match self.uart.front() {
                Some(&(t, b)) if t <= self.t_us => {
                    buf[n] = b;
                    n += 1;
                    self.uart.pop_front();
                }
                _ => break,
            }
        }
        n
    }
}

impl Clock for Sim {
    fn now_us(&mut self) -> u64 {
        self.t_us
    }
}
