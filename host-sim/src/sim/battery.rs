//! The twin's battery: energy drained by the wheel motors, the suction
//! and the electronics, charged on the dock's contacts, and reported as
//! a fuel gauge does (whole percent).
//!
//! The reference robot's figures, with their sources:
//! - **Pack:** 2S2P of a 2,600 mAh 18650 NMC cell (Samsung INR18650-26J
//!   datasheet: 2,600 mAh, 3.6 V nominal, 4.2 V charged): 7.2 V × 5.2 Ah
//!   = 37.4 Wh, the energy of an entry robot vacuum's 14.4 V, 2,600 mAh
//!   pack, in the two cells in series that the reference wiring reads
//!   (`firmware/board/wiring.rs`: the TB6612's 13.5 V rules out a 4S).
//! - **Suction, main and side brush:** 22 W while cleaning: an entry
//!   robot vacuum's rating is 25–35 W in all (iRobot Roomba 600 series:
//!   33 W; Eufy RoboVac 11S: 14.4 V, 2,600 mAh, "up to 100 min" on its
//!   standard setting, about 22 W on average), most of it the fan.
//! - **Electronics:** 1.5 W: the LD06 (its datasheet: 5 V, 180 mA) with
//!   the F411, the motor driver's logic and the regulators' losses.
//! - **Wheels:** 3 W per wheel at full duty, in proportion to the duty
//!   (an N20-class 12 V gear motor near its rated load: 0.25 A).
//! - **Charger:** 19 W into the pack (2.6 A at 7.2–8.4 V: 0.5 C) up to
//!   80 %, then tapering linearly to a tenth of that at 100 % (the
//!   constant-voltage stage of a Li-ion charge); the electronics stay on
//!   from the dock.
//!
//! From full: about 80 minutes of cleaning; 10 % to 80 % in about 85
//! minutes on the dock.

/// The battery's figures.
#[derive(Clone, Copy, Debug)]
pub struct BatterySpec {
    /// Usable energy from full, Wh.
    pub capacity_wh: f64,
    /// Suction and brushes, W (while off the dock).
    pub suction_w: f64,
    /// Electronics and lidar, W (always).
    pub electronics_w: f64,
    /// One wheel motor at full duty, W.
    pub wheel_full_duty_w: f64,
    /// The charger's power into the pack, W, up to `taper_from`.
    pub charger_w: f64,
    /// Share of charge from which the charger's power tapers.
    pub taper_from: f64,
}

/// The reference robot's (see the module's sources).
pub const REFERENCE: BatterySpec = BatterySpec {
    capacity_wh: 37.4,
    suction_w: 22.0,
    electronics_w: 1.5,
    wheel_full_duty_w: 3.0,
    charger_w: 19.0,
    taper_from: 0.8,
};

/// The battery's state, and what it went through.
#[derive(Clone, Debug)]
pub struct Battery {
    /// Figures.
    pub spec: BatterySpec,
    /// Energy left, Wh.
    pub energy_wh: f64,
    /// Lowest charge seen, 0..1.
    pub min_charge: f64,
    /// Energy drawn, Wh.
    pub used_wh: f64,
}

impl Battery {
    /// A full battery.
    pub fn full(spec: BatterySpec) -> Self {
        Self {
            spec,
            energy_wh: spec.capacity_wh,
            min_charge: 1.0,
            used_wh: 0.0,
        }
    }

    /// Charge, 0..1.
    pub fn charge(&self) -> f64 {
        (self.energy_wh / self.spec.capacity_wh).clamp(0.0, 1.0)
    }

    /// What the gauge reports, ‰, in whole percent (as a BMS does).
    pub fn gauge_pm(&self) -> u16 {
        ((self.charge() * 100.0).floor() * 10.0) as u16
    }

    /// Empty: the pack's protection has cut the robot off.
    pub fn flat(&self) -> bool {
        self.energy_wh <= 0.0
    }

    /// `dt_s` seconds with the wheels at `duty` (each −1..1), on the
    /// dock's contacts or not.
    pub fn step(&mut self, dt_s: f64, duty: [f64; 2], on_contacts: bool) {
        let s = self.spec;
        let wheels: f64 = duty.iter().map(|d| d.abs().min(1.0)).sum::<f64>() * s.wheel_full_duty_w;
        let load_w = if on_contacts {
            wheels
        } else {
            wheels + s.suction_w + s.electronics_w
        };
        let mut in_w = 0.0;
        if on_contacts && self.charge() < 1.0 {
            let c = self.charge();
            let taper = if c <= s.taper_from {
                1.0
            } else {
                1.0 - 0.9 * (c - s.taper_from) / (1.0 - s.taper_from)
            };
            in_w = s.charger_w * taper;
        }
        self.energy_wh = (self.energy_wh + (in_w - load_w) * dt_s / 3600.0).min(s.capacity_wh);
        self.used_wh += load_w * dt_s / 3600.0;
        self.min_charge = self.min_charge.min(self.charge());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The figures the module's doc states: about 80 min of cleaning
    /// from full (at the cleaning speed's duty, about 0.6), and 10 % to
    /// 80 % in about 85 min.
    #[test]
    fn run_and_charge_times() {
        let mut b = Battery::full(REFERENCE);
        let mut t = 0.0;
        while !b.flat() {
            b.step(1.0, [0.6, 0.6], false);
            t += 1.0;
        }
        assert!((75.0..90.0).contains(&(t / 60.0)), "{} min", t / 60.0);
        b.energy_wh = 0.1 * b.spec.capacity_wh;
        let mut t = 0.0;
        while b.charge() < 0.8 {
            b.step(1.0, [0.0, 0.0], true);
            t += 1.0;
        }
        assert!((75.0..95.0).contains(&(t / 60.0)), "{} min", t / 60.0);
        assert_eq!(b.gauge_pm(), 800);
    }
}
