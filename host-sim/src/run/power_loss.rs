//! A power loss mid-mission (issue 12): the mission saves its map and its
//! cleaning progress every so often, the power fails, the owner puts the
//! robot back on its dock, and a second mission starts from what was
//! saved: it relocalises at the dock on the saved map and cleans only
//! what is left. Measured on the truth: the floor swept by either run,
//! the floor the second run swept again that the first had swept, and
//! the distance both drove beyond the same mission run without the cut.

use super::executive::Executive;
use super::mission::{run_mission, MissionOptions, MissionReport, MissionTrace};
use crate::io::store::MemStore;
use crate::sim::floor::Floor;
use robovac::mission::{MapMode, State};

/// What the reset cost, on the truth.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ResetFigures {
    /// When the power failed, sim s.
    pub power_loss_s: f64,
    /// How often the progress was saved, sim s.
    pub saved_every_s: f64,
    /// Share of the reachable floor swept by the first run.
    pub first_coverage: f64,
    /// Share swept by either run.
    pub coverage: f64,
    /// Share of the reachable floor the second run swept that the first
    /// had already swept: cleaned twice because of the reset (an upper
    /// bound: a transit across clean floor that any mission drives is
    /// counted too).
    pub reswept: f64,
    /// Cells the second run found marked clean (planning cells, and the
    /// edge pass's contour cells).
    pub cells_restored: u32,
    /// Distance driven by both runs, m.
    pub distance_m: f64,
    /// Distance driven by the same mission without the power loss, m.
    pub uninterrupted_distance_m: f64,
    /// The floor cleaned again because of the reset: the distance both
    /// runs drove beyond the uninterrupted mission's, times the cleaning
    /// width, as a share of the reachable floor (negative when the
    /// second run happened to take a shorter way).
    pub extra_cleaned: f64,
    /// The uninterrupted mission's coverage.
    pub uninterrupted_coverage: f64,
}

/// Both runs and the figures.
pub struct PowerLoss {
    /// The run the power cut short.
    pub first: (MissionReport, MissionTrace),
    /// The run after the reset.
    pub second: (MissionReport, MissionTrace, Floor),
    /// The same mission without the power loss.
    pub uninterrupted: MissionReport,
    /// The reset's cost.
    pub figures: ResetFigures,
}

/// Runs `opts` until the power fails at `at_s` (saving every
/// `every_s`), then again from the dock on what was saved.
pub fn run_power_loss(
    opts: &MissionOptions,
    at_s: f64,
    every_s: f64,
    mut progress: impl FnMut(f64, State, f64),
) -> Result<PowerLoss, String> {
    let mut o1 = opts.clone();
    o1.map_store.progress_every_s = Some(every_s);
    o1.map_store.power_loss_s = Some(at_s);
    let (rep1, trace1, floor1) = run_mission(&o1, &mut progress)?;
    if rep1.finished {
        return Err(format!(
            "the mission finished before the power loss at {at_s} s: choose an earlier time"
        ));
    }
    let Some((store, _)) = trace1.saved_map.clone() else {
        return Err("nothing was saved before the power loss: choose a later time".into());
    };
    let mut o2 = opts.clone();
    o2.mode = MapMode::Unknown;
    o2.map_store.load = Some(store);
    o2.map_store.restore_progress = true;
    let (rep2, trace2, floor2) = run_mission(&o2, &mut progress)?;
    let (rep0, _, _) = run_mission(opts, &mut progress)?;
    let width_m = crate::sim::robot::RobotConfig::default().diameter_m;
    let distance_m = rep1.distance_m + rep2.distance_m;
    let figures = ResetFigures {
        power_loss_s: at_s,
        saved_every_s: every_s,
        first_coverage: rep1.coverage,
        cells_restored: trace2.restored_cells,
        distance_m,
        uninterrupted_distance_m: rep0.distance_m,
        extra_cleaned: (distance_m - rep0.distance_m) * width_m / rep0.floor_m2.max(1e-9),
        uninterrupted_coverage: rep0.coverage,
        ..overlap(&floor1, &floor2)
    };
    Ok(PowerLoss {
        first: (rep1, trace1),
        second: (rep2, trace2, floor2),
        uninterrupted: rep0,
        figures,
    })
}

/// Floor swept by either run, and by both, as shares of the floor.
fn overlap(a: &Floor, b: &Floor) -> ResetFigures {
    let (_, w, h) = a.dims();
    let (mut either, mut both) = (0usize, 0usize);
    for y in 0..h {
        for x in 0..w {
            let (sa, sb) = (a.state(x, y), b.state(x, y));
            either += usize::from(sa == Some(true) || sb == Some(true));
            both += usize::from(sa == Some(true) && sb == Some(true));
        }
    }
    let n = a.floor_cells.max(1) as f64;
    ResetFigures {
        coverage: either as f64 / n,
        reswept: both as f64 / n,
        ..Default::default()
    }
}

/// The power fails now ([`super::mission_map::MapStore::power_loss_s`]).
pub(super) fn power_cut(opts: &MissionOptions, t_us: u64) -> bool {
    opts.map_store
        .power_loss_s
        .is_some_and(|t| t_us >= (t * 1e6) as u64)
}

/// The progress kept through a power loss: every `progress_every_s` the
/// map and the progress saved, as the robot would to its store
/// ([`MissionTrace::saved_map`] keeps the last); and the edge pass's part
/// restored once its pass has started.
pub(super) fn keep_progress(
    opts: &MissionOptions,
    t_us: u64,
    mission: &mut dyn Executive,
    dock: robovac::robot::odometry::Pose,
    trace: &mut MissionTrace,
) -> Result<(), String> {
    if let Some(every) = opts.map_store.progress_every_s {
        let period_us = ((every * 1e6) as u64).max(10_000);
        if t_us % period_us < 10_000 && mission.state() != State::SelfTest {
            let mut store = MemStore::erased();
            let n = mission.save_progress(dock, &mut store)?;
            trace.saved_map = Some((store, n));
        }
    }
    if let (true, Some(store)) = (mission.wants_edge_progress(), &opts.map_store.load) {
        trace.restored_cells += mission
            .restore_edge_progress(&mut store.clone())
            .unwrap_or(0);
    }
    Ok(())
}
