//! A mission's map before it begins, and the owner's rules on it: the
//! map kept between runs (loaded from a store, saved at the end) and the
//! no-go zones and virtual walls, measured on the truth; and the robot's
//! own frame (`--dock-frame`), an empty map centred on the dock.

use robovac::grid::Zone;
use robovac::mission::{MapMode, MissionConfig};
use robovac::robot::lidar_map::EvidenceMap;

use super::mission::{MissionOptions, EVIDENCE_MM};
use super::parts::Capacity;
use crate::io::store::MemStore;
use crate::sim::scan::fill_prior;
use crate::sim::world::World;

/// The map kept between runs: the store a known-mode mission takes its
/// map from (instead of the floor plan), and whether to save the map at
/// the end of a finished mission.
#[derive(Clone, Debug, Default)]
pub struct MapStore {
    /// Start from the map saved here (known mode).
    pub load: Option<MemStore>,
    /// Save the map when the mission finishes ([`MissionTrace::saved_map`]).
    pub save: bool,
    /// Save the map and the cleaning progress this often (sim s), into
    /// [`MissionTrace::saved_map`]: what survives a power loss.
    pub progress_every_s: Option<f64>,
    /// The power fails at this sim time (s): the mission stops there, as
    /// it stands (not finished).
    pub power_loss_s: Option<f64>,
    /// The map loaded (`load`) carries a saved progress: restore it after
    /// the mission begins, so only what is left is cleaned.
    pub restore_progress: bool,
}

/// How far the robot keeps from the owner's zones beyond its body, m:
/// [`robovac::grid::zones::MARGIN_MM`].
pub const ZONE_MARGIN_M: f64 = robovac::grid::zones::MARGIN_MM as f64 / 1000.0;

/// The owner's zones, measured on the truth (reported only when there
/// are any).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct ZoneFigures {
    /// No-go zones and virtual walls set.
    pub count: usize,
    /// Times the true body entered a no-go zone or touched a virtual wall.
    pub entries: usize,
    /// The smallest gap between the true body and a zone, mm (negative:
    /// how deep it reached into one).
    pub min_gap_mm: f64,
    #[serde(skip)]
    inside: bool,
}

impl ZoneFigures {
    /// Figures for `zones`, none when there are none.
    pub fn of(zones: &[Zone]) -> Option<Self> {
        (!zones.is_empty()).then(|| Self {
            count: zones.len(),
            min_gap_mm: f64::INFINITY,
            ..Default::default()
        })
    }

    /// The true body's deepest reach into a zone this period, m (at most
    /// 0 when clear).
    pub fn note(&mut self, deep_m: f64) {
        self.entries += (deep_m > 0.0 && !self.inside) as usize;
        self.inside = deep_m > 0.0;
        self.min_gap_mm = self.min_gap_mm.min(-deep_m * 1000.0);
    }
}

/// The executive's map before it begins: sized to the world; in known
/// mode the floor plan, or the map saved by an earlier run
/// ([`MapStore::load`]); then the owner's zones, with the core's margin.
pub(super) fn prepare_map<const B: usize>(
    map: &mut EvidenceMap<B>,
    world: &World,
    opts: &MissionOptions,
) -> Result<(), String> {
    let known = opts.mode == MapMode::Known;
    fill_prior(
        map,
        world,
        EVIDENCE_MM,
        known && opts.map_store.load.is_none(),
    )?;
    if let Some(store) = &opts.map_store.load {
        let size = (map.width(), map.height(), map.res_mm());
        robovac::robot::map_image::load(&mut store.clone(), map)
            .map_err(|e| format!("saved map: {e}"))?;
        let got = (map.width(), map.height(), map.res_mm());
        if got != size {
            return Err(format!(
                "the saved map ({}x{} cells of {} mm) is not of this home ({}x{} of {} mm)",
                got.0, got.1, got.2, size.0, size.1, size.2
            ));
        }
    }
    map.set_zones(&world.zones, robovac::grid::zones::MARGIN_MM)
        .map_err(|e| e.to_string())
}

/// The firmware in the emulator, its map in `map` (a `side` × `side` map
/// of the image's capacity): the world's prior (known mode), or the
/// dock's frame (`--dock-frame`, the dock at `start`, world m).
pub(super) fn pil_on<const B: usize>(
    pil: &super::pil::PilOptions,
    opts: &MissionOptions,
    cfg: MissionConfig,
    mut map: Box<robovac::robot::lidar_map::EvidenceMap<B>>,
    side: usize,
    world: &World,
    start: (f64, f64),
) -> Result<super::pil::Pil, String> {
    if !opts.dock_frame {
        let known = opts.mode == MapMode::Known;
        return super::pil::Pil::start_on(pil, cfg, map, world, known);
    }
    let frame = dock_frame(&mut map, side, start)?;
    let mut p = super::pil::Pil::start(&pil.elf, pil.log.as_deref(), cfg, &map)?;
    p.frame = frame;
    Ok(p)
}

/// `--dock-frame` is for a first run in unknown mode at the firmware's
/// capacity: what the robot image does.
pub(super) fn check_dock_frame(opts: &MissionOptions, world: &World) -> Result<(), String> {
    if !opts.dock_frame {
        return Ok(());
    }
    let why = if opts.mode != MapMode::Unknown || opts.map_store.load.is_some() {
        "a first run in unknown mode (no --load-map)"
    } else if opts.capacity == Capacity::Host {
        "the firmware's capacity (--capacity fw or fw16)"
    } else if !world.zones.is_empty() {
        "no no-go zones or virtual walls (they are drawn in the world's frame; --no-map-zones)"
    } else if opts.map_store.save || opts.map_store.progress_every_s.is_some() {
        "no saved map (a map in the dock's frame is not of the world's)"
    } else {
        return Ok(());
    };
    Err(format!("--dock-frame needs {why}"))
}

/// The robot's own frame: an empty `side` × `side` map of
/// [`EVIDENCE_MM`] cells with the dock (`start`, world m) at its centre.
pub(super) fn dock_frame<const B: usize>(
    map: &mut robovac::robot::lidar_map::EvidenceMap<B>,
    side: usize,
    start: (f64, f64),
) -> Result<super::executive::Frame, String> {
    map.reset(side as u32, side as u32, EVIDENCE_MM)
        .map_err(|e| format!("map too large for the evidence map: {e}"))?;
    let half = (side as u32 * EVIDENCE_MM / 2) as i32;
    let (x, y) = (
        (start.0 * 1000.0).round() as i32,
        (start.1 * 1000.0).round() as i32,
    );
    Ok(super::executive::Frame {
        offset_mm: (x - half, y - half),
        scrolls: 0,
    })
}
