//! The coarse levels of the scan matcher (Hector SLAM's map pyramid,
//! Kohlbrecher 2011 §IV-C): level k (1..=[`LEVELS`]) has blocks of 2^k
//! evidence cells a side, each holding the share of its cells that are
//! walls, in 4 bits (0..=15 for 0..=1); the coarsest, which only the
//! whole-map search reads, counts wall faces only ([`GLOBAL_LEVEL`]).
//!
//! Why shares, not Hector's "any wall in the block": bilinear
//! interpolation of box-filtered occupancy crosses ½ exactly on a straight
//! wall's face, wherever the face lies in its block, so every level pulls
//! points onto faces (target ½, see [`super::field`]) and a coarse level
//! does not bias the pose by up to half a block (it did: 100 mm at
//! level 2). 4 bits a block: 9.5 KiB for a 12 × 12 m home at 5 cm.
//!
//! Rebuilt from the map when it changes: once in known mode (the prior is
//! fixed), every few revolutions in unknown mode (between rebuilds only
//! the fine level, read live from the map, sees new walls).

use crate::robot::lidar_map::EvidenceMap;

/// Coarse levels above the evidence map's own (10, 20, 40 cm at 5 cm).
pub const LEVELS: usize = 3;

/// The level only the whole-map search reads
/// ([`super::correlative::global`]): it counts wall faces only
/// ([`EvidenceMap::is_wall_face`]), not every wall cell. That search
/// scores a place by how many points land on blocks holding any wall; a
/// prior map built from a vendor's export holds the never-seen space
/// round the home as one solid wall, so nearly every 40 cm block near the
/// home's edge "held a wall", wrong places scored every point, and the
/// true one was not among the kept candidates. Twin scans at 20 random
/// free places of each real home, relocalised over the whole map (found
/// within 30 mm), every wall cell against faces only: S8 6 → 17, z10
/// 4 → 20, 1c 15 → 20, S6 13 → 20, 3790 9 → 20, l10su 2 → 15 of 20.
/// A block also counts the faces one cell beyond its edges ([`count_in`]):
/// a return off a face lying on a block border falls in the block before
/// the wall.
/// The finer levels keep every wall cell: tracking reads them, and their
/// shares put a face's ½ crossing where the face is.
pub const GLOBAL_LEVEL: usize = 3;

/// The coarse levels, packed two blocks a byte, in `MW` 32-bit words.
pub struct Pyramid<const MW: usize> {
    words: [u32; MW],
    /// Per level k (index k − 1): width, height, first nibble.
    dims: [(u32, u32, u32); LEVELS],
    ready: bool,
}

impl<const MW: usize> Default for Pyramid<MW> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const MW: usize> Pyramid<MW> {
    /// Empty levels (not ready).
    pub const fn new() -> Self {
        Self {
            words: [0; MW],
            dims: [(0, 0, 0); LEVELS],
            ready: false,
        }
    }

    /// True once built for a map.
    pub fn ready(&self) -> bool {
        self.ready
    }

    /// Rebuilds every level from `map`'s walls ([`EvidenceMap::is_wall`]
    /// with `prior_only`). False when the map is too large for `MW` words
    /// (the levels are then not ready).
    pub fn build<const EV: usize>(&mut self, map: &EvidenceMap<EV>, prior_only: bool) -> bool {
        let (w, h) = (map.width(), map.height());
        let mut first = 0u32;
        for (k, d) in self.dims.iter_mut().enumerate() {
            let s = 1u32 << (k + 1);
            let (lw, lh) = (w.div_ceil(s), h.div_ceil(s));
            *d = (lw, lh, first);
            first = first.saturating_add(lw.saturating_mul(lh));
        }
        self.ready = false;
        if first as usize > MW * 8 {
            return false;
        }
        self.words.iter_mut().for_each(|x| *x = 0);
        // Each level counts the cells of its blocks (up to 4^k), stored
        // as a share of 15.
        for k in 1..=LEVELS {
            let Some(&(lw, lh, _)) = self.dims.get(k - 1) else {
                continue;
            };
            let side = 1i32 << k;
            for by in 0..lh as i32 {
                for bx in 0..lw as i32 {
                    let n = if k == GLOBAL_LEVEL {
                        count_in(bx, by, side, 1, |x, y| map.is_wall_face(x, y, prior_only))
                    } else {
                        count_in(bx, by, side, 0, |x, y| map.is_wall(x, y, prior_only))
                    };
                    let share = (n * 15).div_ceil((side * side) as u32);
                    self.put(k, bx, by, share.min(15));
                }
            }
        }
        self.ready = true;
        true
    }

    fn put(&mut self, k: usize, bx: i32, by: i32, v: u32) {
        if let Some(i) = self.index(k, bx, by) {
            if let Some(w) = self.words.get_mut(i >> 3) {
                let sh = (i & 7) * 4;
                *w = (*w & !(15 << sh)) | (v << sh);
            }
        }
    }

    fn index(&self, k: usize, bx: i32, by: i32) -> Option<usize> {
        let &(lw, lh, first) = self.dims.get(k.wrapping_sub(1))?;
        if bx < 0 || by < 0 || bx as u32 >= lw || by as u32 >= lh {
            return None;
        }
        Some((first + by as u32 * lw + bx as u32) as usize)
    }

    /// The wall share (0..=15) of level `k`'s block at column `bx`, row
    /// `by` from the top (off the level: 0).
    #[inline]
    pub fn share(&self, k: usize, bx: i32, by: i32) -> u32 {
        self.index(k, bx, by).map_or(0, |i| nibble(&self.words, i))
    }

    /// One level's view for tight loops (no per-read dimension lookup).
    pub fn level(&self, k: usize) -> Level<'_> {
        let (lw, lh, first) = self
            .dims
            .get(k.wrapping_sub(1))
            .copied()
            .unwrap_or((0, 0, 0));
        Level {
            words: &self.words,
            lw: lw as i32,
            lh: lh as i32,
            first: first as usize,
        }
    }

    /// A level's size in blocks.
    pub fn dims(&self, k: usize) -> (u32, u32) {
        self.dims
            .get(k.wrapping_sub(1))
            .map_or((0, 0), |&(w, h, _)| (w, h))
    }
}

/// One coarse level, borrowed ([`Pyramid::level`]).
pub struct Level<'a> {
    words: &'a [u32],
    lw: i32,
    lh: i32,
    first: usize,
}

impl Level<'_> {
    /// The share (0..=15) at column `bx`, row `by` from the top (off the
    /// level: 0).
    #[inline]
    pub fn share(&self, bx: i32, by: i32) -> u32 {
        if bx < 0 || by < 0 || bx >= self.lw || by >= self.lh {
            return 0;
        }
        let i = self.first + (by * self.lw + bx) as usize;
        nibble(self.words, i)
    }
}

/// Cells for which `hit` holds in block (`bx`, `by`) of `side` cells,
/// widened by `reach` cells beyond its edges (its corners aside).
///
/// The whole-map level counts wall faces one cell beyond: a return lies
/// on the face's surface, which is a cell border, so when a wall's face
/// is also a block border every return off it falls in the free block
/// before the wall. Counting only the block's own faces, such a wall
/// scored nothing and the true place lost to clutter elsewhere (the S8
/// home, kidnapped beside a wall at x = 6.40 m, a block border: 27 of 32
/// points hit at the exact pose, wrong places 29–31; 12 of 150 points
/// missed, all on that wall).
fn count_in(bx: i32, by: i32, side: i32, reach: i32, hit: impl Fn(i32, i32) -> bool) -> u32 {
    let mut n = 0;
    for dy in -reach..side + reach {
        for dx in -reach..side + reach {
            let edge_x = dx < 0 || dx >= side;
            let edge_y = dy < 0 || dy >= side;
            if !(edge_x && edge_y) && hit(bx * side + dx, by * side + dy) {
                n += 1;
            }
        }
    }
    n
}

/// The `i`-th 4-bit share of the packed words (0 past the end).
#[inline(always)]
fn nibble(words: &[u32], i: usize) -> u32 {
    words.get(i >> 3).map_or(0, |w| (w >> ((i & 7) * 4)) & 15)
}
