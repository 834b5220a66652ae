//! The twin's battery in a mission: drained every control period by what
//! the robot does, charged on the dock's contacts, read by the executive
//! as a fuel gauge's state of charge; and the report's battery figures.

use crate::sim::battery::{Battery, BatterySpec};
use crate::sim::robot::Sim;

/// On the contacts: the true body within this of the dock, m...
const CONTACT_M: f64 = 0.1;
/// ...and the heading within this, rad (15°: a dock's funnel and its
/// sprung contacts take up the rest).
const CONTACT_RAD: f64 = 0.26;

/// The battery and where its charger is.
pub struct Power {
    /// The twin's battery (None: the robot has no gauge; the executive
    /// keeps to its time budget).
    pub battery: Option<Battery>,
    /// The true dock pose: m, m, rad.
    dock: (f64, f64, f64),
}

impl Power {
    /// A full battery of `spec` at the dock `dock`, or none.
    pub fn new(spec: Option<BatterySpec>, dock: (f64, f64, f64)) -> Self {
        Self {
            battery: spec.map(Battery::full),
            dock,
        }
    }

    /// One control period of `dt_s` with the motors as the twin has them.
    pub fn step(&mut self, sim: &Sim, dt_s: f64) {
        let Some(b) = self.battery.as_mut() else {
            return;
        };
        let (x, y, th) = sim.pose;
        let (dx, dy, dth) = self.dock;
        let dh = super::drive::wrap(th - dth);
        let on = (x - dx).hypot(y - dy) <= CONTACT_M && dh.abs() <= CONTACT_RAD;
        b.step(dt_s, sim.duty(), on);
    }

    /// The gauge's reading for the executive, ‰.
    pub fn gauge_pm(&self) -> Option<u16> {
        self.battery.as_ref().map(Battery::gauge_pm)
    }

    /// The pack's protection cut the robot off.
    pub fn flat(&self) -> bool {
        self.battery.as_ref().is_some_and(Battery::flat)
    }
}

/// The battery's figures in the report.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct BatteryFigures {
    /// The pack, Wh.
    pub capacity_wh: f64,
    /// Energy drawn over the mission, Wh.
    pub used_wh: f64,
    /// The lowest charge, %.
    pub min_charge_pct: f64,
    /// The charge at the end, %.
    pub end_charge_pct: f64,
    /// The pack ran flat.
    pub ran_flat: bool,
}

impl BatteryFigures {
    /// The figures of `p`'s battery (None without one).
    pub fn of(p: &Power) -> Option<Self> {
        p.battery.as_ref().map(|b| Self {
            capacity_wh: b.spec.capacity_wh,
            used_wh: b.used_wh,
            min_charge_pct: b.min_charge * 100.0,
            end_charge_pct: b.charge() * 100.0,
            ran_flat: b.flat(),
        })
    }
}
