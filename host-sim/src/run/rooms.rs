//! The rooms a mission found ([`robovac::grid::rooms`], split when a
//! known-mode mission begins) as the host sees them: their labels on the
//! planning cells, for the SVG's tint, and their agreement with the
//! vendor's own segments when the map is a ValetudoMap.

use robovac::mission::MissionParts;

use crate::io::maps::MapData;

/// The planning cells' rooms at the end of a mission.
#[derive(Clone, Debug, Default)]
pub struct RoomView {
    /// Planning cell side, m.
    pub cell_m: f64,
    /// The planning grid's width and height, cells.
    pub size: (u32, u32),
    /// The evidence map's height, m (rows run from its top).
    pub map_h_m: f64,
    /// Room of each planning cell, row-major from the top (0: none).
    pub labels: Vec<u8>,
}

impl RoomView {
    /// The rooms of `parts` (planning cells of `cell_mm`, evidence map
    /// `map_h_m` high); none when it found fewer than two.
    pub fn of(parts: &dyn MissionParts, cell_mm: u32, map_h_m: f64) -> Option<Self> {
        let (w, h) = parts.planning_size();
        let labels: Vec<u8> = (0..h as i32)
            .flat_map(|y| (0..w as i32).map(move |x| (x, y)))
            .map(|(x, y)| parts.room_of(x, y))
            .collect();
        (labels.iter().max().copied().unwrap_or(0) > 1).then(|| Self {
            cell_m: cell_mm as f64 / 1000.0,
            size: (w, h),
            map_h_m,
            labels,
        })
    }

    /// The room under world point (x, y) m (0: none).
    pub fn room_at(&self, x: f64, y: f64) -> u8 {
        let gx = (x / self.cell_m).floor();
        let gy = ((self.map_h_m - y) / self.cell_m).floor();
        if gx < 0.0 || gy < 0.0 || gx >= self.size.0 as f64 || gy >= self.size.1 as f64 {
            return 0;
        }
        let i = gy as usize * self.size.0 as usize + gx as usize;
        self.labels.get(i).copied().unwrap_or(0)
    }

    /// Every cell given the room of the nearest labelled one (4-neighbour
    /// wavefront, ties to the first found): the strips along the walls,
    /// which the configuration space leaves out, belong to their rooms.
    pub fn filled(&self) -> Self {
        let (w, h) = (self.size.0 as usize, self.size.1 as usize);
        let mut labels = self.labels.clone();
        let mut front: std::collections::VecDeque<usize> =
            (0..labels.len()).filter(|&i| labels[i] != 0).collect();
        while let Some(i) = front.pop_front() {
            let (x, y) = (i % w, i / w);
            let near = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then(|| i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then(|| i + w),
            ];
            for j in near.into_iter().flatten() {
                if labels[j] == 0 {
                    labels[j] = labels[i];
                    front.push_back(j);
                }
            }
        }
        Self {
            labels,
            ..self.clone()
        }
    }

    /// Rooms found.
    pub fn count(&self) -> u8 {
        self.labels.iter().max().copied().unwrap_or(0)
    }
}

/// The evidence map's height, m, for a world `h_m` high at `res_mm`
/// cells (as [`crate::sim::scan::fill_prior`] sizes it).
pub fn evidence_h_m(h_m: f64, res_mm: u32) -> f64 {
    ((h_m * 1000.0).round() as u32).div_ceil(res_mm) as f64 * res_mm as f64 / 1000.0
}

/// The mission report's rooms.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct RoomFigures {
    /// Rooms found when the mission began.
    pub found: u8,
    /// Rooms the robot entered (every one, when it finished).
    pub entered: u32,
    /// Against the vendor's segments (ValetudoMaps).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agreement: Option<RoomAgreement>,
}

impl RoomFigures {
    /// The figures of a mission's rooms, none without rooms.
    pub fn of(
        map: &MapData,
        rooms: Option<&RoomView>,
        c: &robovac::mission::Counters,
    ) -> Option<Self> {
        let rooms = rooms?;
        Some(Self {
            found: rooms.count(),
            entered: c.rooms_entered,
            agreement: agreement(map, &rooms.filled()),
        })
    }
}

/// Our rooms against the vendor's segments, over the vendor's room pixels.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct RoomAgreement {
    /// The vendor's rooms.
    pub vendor_rooms: usize,
    /// Ours.
    pub our_rooms: usize,
    /// Share of the vendor's room pixels inside the one of our rooms that
    /// holds most of their room (how whole the vendor's rooms stay), %.
    pub recall_pct: f64,
    /// Share of the pixels of each of our rooms inside the vendor's room
    /// that holds most of it (how pure ours are), %.
    pub precision_pct: f64,
}

/// Our rooms against the segments of a ValetudoMap (none for other maps).
pub fn agreement(map: &MapData, rooms: &RoomView) -> Option<RoomAgreement> {
    let vendor = &map.extras.as_ref()?.rooms;
    if vendor.is_empty() {
        return None;
    }
    let n = rooms.count() as usize + 1;
    // overlap[v][o]: vendor room v's pixels in our room o (0: in none).
    let overlap: Vec<Vec<u64>> = vendor
        .iter()
        .map(|r| {
            let mut row = vec![0u64; n];
            for &(x, y) in &r.points_m {
                if let Some(c) = row.get_mut(rooms.room_at(x, y) as usize) {
                    *c += 1;
                }
            }
            row
        })
        .collect();
    let total: u64 = overlap.iter().flatten().sum();
    let recall: u64 = overlap
        .iter()
        .map(|row| row.iter().skip(1).max().copied().unwrap_or(0))
        .sum();
    let ours: u64 = (1..n)
        .map(|o| overlap.iter().map(|row| row[o]).max().unwrap_or(0))
        .sum();
    let in_ours: u64 = overlap
        .iter()
        .map(|row| row.iter().skip(1).sum::<u64>())
        .sum();
    Some(RoomAgreement {
        vendor_rooms: vendor.len(),
        our_rooms: n - 1,
        recall_pct: 100.0 * recall as f64 / total.max(1) as f64,
        precision_pct: 100.0 * ours as f64 / in_ours.max(1) as f64,
    })
}
