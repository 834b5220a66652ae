//! The battery's state of charge from its resting voltage: the
//! open-circuit curve of a Li-ion (NMC) cell, piecewise linear.
//!
//! The executive decides on a state of charge in permille
//! ([`crate::mission::Mission::set_charge`]). A pack with a fuel gauge
//! (a BMS reporting its coulomb count, as robot vacuums' packs do) gives
//! it directly; a board that has only the pack's voltage on an ADC pin
//! converts it here. The curve is a typical 18650 NMC cell's at rest
//! (0.2 C discharge curves in cell datasheets, e.g. Samsung INR18650-26J):
//! 4.20 V full, a long plateau at 3.7–3.9 V, a knee below 3.5 V. Under
//! load the pack reads low (its internal resistance), so the charge is
//! under-estimated while driving: the safe side for going home. The flat
//! middle makes it coarse there (10 mV ≈ 3 %), which is why a gauge is
//! the better part.

/// (cell mV, charge ‰), rising: the open-circuit curve.
const CURVE: [(u32, u32); 12] = [
    (3000, 0),
    (3450, 50),
    (3680, 100),
    (3740, 200),
    (3770, 300),
    (3790, 400),
    (3820, 500),
    (3870, 600),
    (3920, 700),
    (3980, 800),
    (4060, 900),
    (4200, 1000),
];

/// The charge (‰, 0..=1000) of a pack of `cells` cells in series at
/// `pack_mv` (resting); 0 cells reads as empty. Saturates outside the
/// curve.
pub fn charge_from_mv(pack_mv: u32, cells: u32) -> u16 {
    let Some(cell_mv) = pack_mv.checked_div(cells) else {
        return 0;
    };
    let mut lo = (0, 0);
    for &(mv, pm) in CURVE.iter() {
        if cell_mv <= mv {
            let (mv0, pm0) = lo;
            if mv == mv0 {
                return pm as u16;
            }
            return (pm0 + (pm - pm0) * (cell_mv.max(mv0) - mv0) / (mv - mv0)) as u16;
        }
        lo = (mv, pm);
    }
    1000
}

/// The resting voltage of one cell at `charge_pm` ‰ (the curve's
/// inverse; for the twin's battery and the tests).
pub fn cell_mv_at(charge_pm: u32) -> u32 {
    let mut lo = (3000, 0);
    for &(mv, pm) in CURVE.iter() {
        if charge_pm <= pm {
            let (mv0, pm0) = lo;
            if pm == pm0 {
                return mv;
            }
            return mv0 + (mv - mv0) * (charge_pm.max(pm0) - pm0) / (pm - pm0);
        }
        lo = (mv, pm);
    }
    4200
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_and_round_trip() {
        assert_eq!(charge_from_mv(4 * 4200, 4), 1000);
        assert_eq!(charge_from_mv(4 * 4300, 4), 1000);
        assert_eq!(charge_from_mv(4 * 3000, 4), 0);
        assert_eq!(charge_from_mv(0, 4), 0);
        assert_eq!(charge_from_mv(16_800, 0), 0);
        for pm in (0..=1000).step_by(10) {
            let mv = cell_mv_at(pm);
            let back = charge_from_mv(4 * mv, 4) as i64;
            // Integer division loses at most a few ‰ on the steep ends.
            assert!(
                (back - pm as i64).abs() <= 5,
                "{pm} ‰ -> {mv} mV -> {back} ‰"
            );
        }
    }

    #[test]
    fn monotone() {
        let mut last = 0;
        for mv in (2900..4300).step_by(5) {
            let pm = charge_from_mv(4 * mv, 4);
            assert!(pm >= last);
            last = pm;
        }
    }
}
