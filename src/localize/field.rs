//! The matcher's view of one map level: is there a wall at a cell, and the
//! bilinear interpolation of that 0/1 layer at a world point with its
//! gradient (Hector SLAM, Kohlbrecher 2011, eq. 4–6).
//!
//! Cells are read with rows from the map's top, as the evidence map
//! addresses them; the interpolation runs between cell centres.
//!
//! **Where a point should land**: where the interpolated value is ½, on
//! every level. On the fine level (0) the layer is the wall cells (0 or
//! 1), and ½ lies on the boundary between a free cell and a wall cell: the
//! wall's face. A point in front of the face is pulled onto it, one behind
//! it pushed back out, so a wall two cells thick gives no plateau to slide
//! along (Hector's own target of 1 at wall cell centres does, and biased
//! our first version by 10–20 mm). Coarse levels hold each block's share
//! of walls ([`super::pyramid`]), whose interpolation also crosses ½ on a
//! straight face.

use super::pyramid::Pyramid;
use crate::robot::lidar_map::EvidenceMap;

/// The wall value at a point and its gradient.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sample {
    /// Interpolated wall value, Q8 (0..=256).
    pub m_q8: i32,
    /// ∂value/∂x per level cell, Q8 (east).
    pub gx_q8: i32,
    /// ∂value/∂y per level cell, Q8 (north).
    pub gy_q8: i32,
}

/// One level: 0 is the evidence map itself (read live), 1..=LEVELS the
/// pyramid's.
pub struct Field<'a, const EV: usize, const MW: usize> {
    map: &'a EvidenceMap<EV>,
    pyramid: &'a Pyramid<MW>,
    level: usize,
    prior_only: bool,
    cell_mm: i32,
    top_mm: i32,
}

impl<'a, const EV: usize, const MW: usize> Field<'a, EV, MW> {
    /// Level `level` of `map` (walls per `prior_only`) and `pyramid`.
    pub fn new(
        map: &'a EvidenceMap<EV>,
        pyramid: &'a Pyramid<MW>,
        level: usize,
        prior_only: bool,
    ) -> Self {
        let res = map.res_mm().clamp(1, 1 << 20) as i32;
        Self {
            map,
            pyramid,
            level,
            prior_only,
            cell_mm: res << level.min(8),
            top_mm: (map.height() as i64 * res as i64).clamp(0, i32::MAX as i64) as i32,
        }
    }

    /// This level's cell side, mm.
    pub fn cell_mm(&self) -> i32 {
        self.cell_mm
    }

    /// Where points should land, Q8 of the wall value (module doc).
    pub fn target_q8(&self) -> i32 {
        128
    }

    /// Whether a sample counts as a point on a wall: near a face (within
    /// about 0.4 cell on the fine level).
    #[inline]
    pub fn inlier(&self, s: &Sample) -> bool {
        (s.gx_q8 != 0 || s.gy_q8 != 0) && (s.m_q8 - 128).abs() <= 100
    }

    /// The wall value of a cell, Q4 (0..=15): fine level 0 or 15, coarse
    /// levels the block's share; column `bx`, row `by` from the top.
    #[inline]
    pub fn wall(&self, bx: i32, by: i32) -> i32 {
        if self.level == 0 {
            self.map.is_wall(bx, by, self.prior_only) as i32 * 15
        } else {
            self.pyramid.share(self.level, bx, by) as i32
        }
    }

    /// Level cell (column, row from the top) and the Q8 position inside
    /// it, measured from the cell centre grid (see the module doc).
    #[inline]
    fn locate(&self, x_mm: i32, y_mm: i32) -> (i32, i32, i32, i32) {
        // i32 throughout (the Cortex-M4 divides 32-bit integers in
        // hardware; a 64-bit division is a library call of ~100 cycles):
        // positions are clamped to ±2^22 mm (4 km), so ×256 fits.
        let c = self.cell_mm.max(1);
        let x = x_mm.clamp(-(1 << 22), 1 << 22);
        let t =
            (self.top_mm.min(1 << 22) - y_mm.clamp(-(1 << 22), 1 << 22)).clamp(-(1 << 23), 1 << 23);
        let u = (x * 256).div_euclid(c) - 128;
        let t = (t * 256).div_euclid(c) - 128;
        (u >> 8, t >> 8, u & 255, t & 255)
    }

    /// The wall value and gradient at world point (x, y) mm.
    #[inline]
    pub fn sample(&self, x_mm: i32, y_mm: i32) -> Sample {
        let (i, j, fu, ft) = self.locate(x_mm, y_mm);
        let m00 = self.wall(i, j);
        let m10 = self.wall(i + 1, j);
        let m01 = self.wall(i, j + 1);
        let m11 = self.wall(i + 1, j + 1);
        let (gu, gt) = (256 - fu, 256 - ft);
        // Q8 · Q8 · Q4 → Q8 by /(256 · 15).
        let m = gu * gt * m00 + fu * gt * m10 + gu * ft * m01 + fu * ft * m11;
        let du = gt * (m10 - m00) + ft * (m11 - m01);
        let dt = gu * (m01 - m00) + fu * (m11 - m10);
        Sample {
            m_q8: m / (256 * 15),
            gx_q8: du / 15,
            // Rows grow southward: north is −t.
            gy_q8: -dt / 15,
        }
    }
}
