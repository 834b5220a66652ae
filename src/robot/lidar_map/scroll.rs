//! The evidence map under a scrolling map (issue 11 §3, [`crate::mission`]'s
//! scroll): moving every cell by whole cells, and the boxes of what the
//! lidar has seen that a scroll must keep.

use super::{take_box, union_box, CellBox, EvidenceMap, FREE_AT, NO_CELLS};

impl<const B: usize> EvidenceMap<B> {
    /// Moves every cell's evidence `dx` columns right and `dy` rows down
    /// (the map scrolling under a robot that nears its edge, issue 11 §3:
    /// [`crate::mission`]'s scroll); the strip left behind becomes unknown
    /// and what moves past the edge is forgotten. World point (x, y) mm
    /// is then at (x + dx·res, y − dy·res). The whole map counts as
    /// changed. Refused (false, nothing moved) while owner's zones are
    /// set: they are drawn in the map's frame.
    pub fn shift(&mut self, dx: i32, dy: i32) -> bool {
        if !self.zones.is_empty() {
            return false;
        }
        let (w, h) = (self.width, self.height);
        crate::grid::shift::for_shift(w, h, dx, dy, |d, s| {
            let v = s.map_or(0, |s| self.get(s));
            self.put(d, v);
        });
        if w > 0 && h > 0 {
            self.changed = (0, 0, w as i32 - 1, h as i32 - 1);
        }
        true
    }

    /// The box of the cells the lidar has seen (evidence not 0), what a
    /// scroll must keep on the map, and the box of the free cells, which
    /// reaches an edge where the map cuts through floor; None when none
    /// is seen. One pass over the cells' bytes (a byte of two unknown
    /// cells is 0).
    pub fn seen_boxes(&self) -> Option<(CellBox, CellBox)> {
        let w = self.width as usize;
        let n = w * self.height as usize;
        let (mut seen, mut free) = (NO_CELLS, NO_CELLS);
        for (k, &byte) in self.cell_bytes().iter().enumerate() {
            if byte == 0 {
                continue;
            }
            for i in [2 * k, 2 * k + 1] {
                let e = if i < n { self.get(i) } else { 0 };
                // Checked: w is not 0 here (i < n), but the firmware must
                // link no panicking branch (issue 11 §6).
                if let (true, Some(x), Some(y)) = (e != 0, i.checked_rem(w), i.checked_div(w)) {
                    let (x, y) = (x as i32, y as i32);
                    seen = union_box(seen, (x, y, x, y));
                    if e <= FREE_AT {
                        free = union_box(free, (x, y, x, y));
                    }
                }
            }
        }
        Some((take_box(&mut seen)?, free))
    }
}

#[cfg(test)]
mod tests {
    use crate::grid::Zone;
    use crate::robot::lidar_map::{evidence_bytes, CellState, EvidenceMap, PRIOR_WALL};

    /// A shift moves each counter (a wall, a free cell, a contact) by
    /// whole cells, forgets what passes the edge, leaves the strip behind
    /// unknown, moves the seen box with it and marks the whole map
    /// changed; world point (x, y) is then at (x + dx·res, y − dy·res).
    #[test]
    fn shift_moves_cells_and_the_seen_box() {
        let mut m: EvidenceMap<{ evidence_bytes(20 * 10) }> = EvidenceMap::new();
        m.reset(20, 10, 50).unwrap();
        m.set_state(3, 4, CellState::Occupied);
        m.set_state(4, 4, CellState::Free);
        m.set_state(19, 0, CellState::Occupied);
        assert!(m.mark_contact(2 * 50 + 10, (10 - 1 - 7) * 50 + 10));
        assert_eq!(m.seen_boxes(), Some(((2, 0, 19, 7), (4, 4, 4, 4))));
        let _ = m.take_changed();
        let before = m.cell_of(3 * 50 + 25, 5 * 50 + 25);
        assert!(m.shift(5, -2));
        assert_eq!(m.state(8, 2), CellState::Occupied);
        assert_eq!(m.state(9, 2), CellState::Free);
        assert_eq!(m.evidence(7, 5), PRIOR_WALL);
        assert_eq!(m.state(3, 4), CellState::Unknown);
        // (19, 0) went past the east edge; the west strip is unknown.
        assert_eq!(m.seen_boxes(), Some(((7, 2, 9, 5), (9, 2, 9, 2))));
        assert_eq!(m.take_changed(), Some((0, 0, 19, 9)));
        let after = m.cell_of(3 * 50 + 25 + 5 * 50, 5 * 50 + 25 + 2 * 50);
        assert_eq!((after.0 - before.0, after.1 - before.1), (5, -2));
        // Zones are drawn in the map's frame: no shift with them.
        m.set_zones(
            &[Zone::NoGo {
                x0_mm: 0,
                y0_mm: 0,
                x1_mm: 100,
                y1_mm: 100,
            }],
            0,
        )
        .unwrap();
        assert!(!m.shift(1, 0));
        m.reset(20, 10, 50).unwrap();
        assert_eq!(m.seen_boxes(), None);
    }
}
