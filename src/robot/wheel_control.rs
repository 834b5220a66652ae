//! Wheel speed control: (v, ω) in mm/s and mrad/s to per-wheel setpoints,
//! an integer PI per wheel with feed-forward and anti-windup, and stall
//! detection.
//!
//! Per wheel: duty = ff·setpoint + kp·error + integral, in permille, with
//! gains in Q8 (duty permille per mm/s × 256). The integral only grows
//! while the output is not saturated in the same direction (conditional
//! integration), so it does not wind up against the duty limit. A wheel
//! that is driven with |duty| ≥ `stall_duty_pm` and produces no tick for
//! `stall_ms` raises a stall fault, and its motor output drops to zero
//! until [`WheelControl::clear_fault`].

/// Gains and limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WheelGains {
    /// Feed-forward, duty permille per mm/s, Q8.
    pub kff_q8: i32,
    /// Proportional gain, duty permille per mm/s of error, Q8.
    pub kp_q8: i32,
    /// Integral gain, duty permille per (mm/s · s), Q8.
    pub ki_q8: i32,
    /// Duty limit, permille.
    pub max_duty_pm: i32,
    /// Duty above which a wheel that does not turn is stalled, permille.
    pub stall_duty_pm: i32,
    /// How long without ticks at high duty makes a stall, ms.
    pub stall_ms: u32,
}

/// Which wheel stalled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WheelFault {
    /// The left wheel.
    LeftStall,
    /// The right wheel.
    RightStall,
}

#[derive(Clone, Copy, Debug, Default)]
struct Pi {
    integ_pm_q8: i64,
    no_tick_us: u32,
}

/// Both wheels' controllers.
#[derive(Clone, Debug)]
pub struct WheelControl {
    gains: WheelGains,
    wheelbase_mm: i32,
    left: Pi,
    right: Pi,
    fault: Option<WheelFault>,
}

/// Per-wheel setpoints in mm/s for a body velocity.
pub fn wheel_setpoints(v_mm_s: i32, w_mrad_s: i32, wheelbase_mm: i32) -> (i32, i32) {
    let half = (w_mrad_s as i64 * wheelbase_mm as i64 / 2000) as i32;
    (v_mm_s - half, v_mm_s + half)
}

impl WheelControl {
    /// A controller.
    pub const fn new(gains: WheelGains, wheelbase_mm: i32) -> Self {
        Self {
            gains,
            wheelbase_mm,
            left: Pi {
                integ_pm_q8: 0,
                no_tick_us: 0,
            },
            right: Pi {
                integ_pm_q8: 0,
                no_tick_us: 0,
            },
            fault: None,
        }
    }

    /// The latched fault, if any.
    pub fn fault(&self) -> Option<WheelFault> {
        self.fault
    }

    /// Clears a fault and the integrators.
    pub fn clear_fault(&mut self) {
        self.fault = None;
        self.left = Pi::default();
        self.right = Pi::default();
    }

    /// One control period of `dt_us`: body velocity command, measured wheel
    /// speeds (mm/s) and whether each wheel ticked this period. Returns the
    /// duties (permille).
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        v_mm_s: i32,
        w_mrad_s: i32,
        meas_left_mm_s: i32,
        meas_right_mm_s: i32,
        left_ticked: bool,
        right_ticked: bool,
        dt_us: u32,
    ) -> (i16, i16) {
        let (sl, sr) = wheel_setpoints(v_mm_s, w_mrad_s, self.wheelbase_mm);
        if self.fault.is_some() {
            return (0, 0);
        }
        let g = self.gains;
        let dl = pi_step(&mut self.left, &g, sl, meas_left_mm_s, left_ticked, dt_us);
        let dr = pi_step(
            &mut self.right,
            &g,
            sr,
            meas_right_mm_s,
            right_ticked,
            dt_us,
        );
        if self.left.no_tick_us >= g.stall_ms.saturating_mul(1000) {
            self.fault = Some(WheelFault::LeftStall);
        } else if self.right.no_tick_us >= g.stall_ms.saturating_mul(1000) {
            self.fault = Some(WheelFault::RightStall);
        }
        if self.fault.is_some() {
            return (0, 0);
        }
        (dl as i16, dr as i16)
    }
}

fn pi_step(pi: &mut Pi, g: &WheelGains, set: i32, meas: i32, ticked: bool, dt_us: u32) -> i32 {
    let err = (set - meas) as i64;
    let ff = g.kff_q8 as i64 * set as i64;
    let p = g.kp_q8 as i64 * err;
    let max = (g.max_duty_pm as i64) << 8;
    let unsat = ff + p + pi.integ_pm_q8;
    // Conditional integration: not while saturated in the error's direction.
    let pushing_up = unsat >= max && err > 0;
    let pushing_down = unsat <= -max && err < 0;
    if !pushing_up && !pushing_down {
        pi.integ_pm_q8 += g.ki_q8 as i64 * err * dt_us as i64 / 1_000_000;
        pi.integ_pm_q8 = pi.integ_pm_q8.max(-max).min(max);
    }
    let duty = ((ff + p + pi.integ_pm_q8) >> 8)
        .max(-(g.max_duty_pm as i64))
        .min(g.max_duty_pm as i64);
    if duty.abs() >= g.stall_duty_pm as i64 && !ticked {
        pi.no_tick_us = pi.no_tick_us.saturating_add(dt_us);
    } else {
        pi.no_tick_us = 0;
    }
    duty as i32
}
