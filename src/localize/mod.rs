//! Pose correction: the lidar scan matched against the map once per
//! revolution, so the robot knows where it is when its wheels slip.
//!
//! **Method: multi-resolution Gauss–Newton scan-to-map matching** (Hector
//! SLAM, Kohlbrecher et al., "A Flexible and Scalable SLAM System with
//! Full 3D Motion Estimation", SSRR 2011, §IV). Each scan point is placed
//! on the map by the pose guess; the map's wall layer, bilinearly
//! interpolated, gives how well it lands and which way to move; a
//! 3 × 3 normal-equation solve moves the pose; coarse levels (10, 20 cm
//! and 40 cm blocks holding their share of walls) widen the basin before
//! the 5 cm level settles it.
//! Chosen over a correlative search (Olson 2009) for tracking because it
//! costs a few hundred thousand instructions per revolution instead of
//! millions, needs no precomputed likelihood field (the field of a
//! 12 × 12 m home at 5 cm is 56 KiB; our coarse levels are 9.5 KiB), and its normal matrix is the information matrix, the
//! conditioning test the fusion needs for free. Where the guess may be
//! far off (the start, a kidnap) a correlative search on the coarse levels
//! ([`correlative`]) finds the basin first, as Cartographer's real-time
//! matcher seeds its optimiser (Hess et al. 2016, §V).
//!
//! **Unmapped points do not pull.** A point whose four surrounding cells
//! hold no wall has zero gradient: a person in the middle of a room adds
//! nothing to the normal equations. Only points that land within a cell
//! of a wall count, and a match is accepted only when enough of them do.
//!
//! Integer throughout: positions in mm, headings in µrad, map values and
//! gradients in Q8, the solve in i128.
//!
//! Files: [`pyramid`] the coarse wall levels; [`field`] the interpolated
//! wall value and its gradient; [`points`] the de-skewed scan;
//! [`trail`] the floor the body swept;
//! [`gauss_newton`] the refinement; [`correlative`] the wide searches;
//! [`fusion`] what is accepted, and the lost-robot detection.

pub mod correlative;
pub mod field;
pub mod fusion;
pub mod gauss_newton;
pub mod points;
pub mod pyramid;
pub mod track;
pub mod trail;

pub use fusion::{Fusion, LocStats};
pub use points::{ScanPoints, MATCH_POINTS};
pub use pyramid::{Pyramid, LEVELS};

/// A pose in the matcher's units: position mm, heading µrad.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PoseU {
    /// East, mm.
    pub x_mm: i32,
    /// North, mm.
    pub y_mm: i32,
    /// Heading, µrad (counter-clockwise from east).
    pub theta_urad: i64,
}

/// Why a match was not accepted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MatchError {
    /// Fewer usable points than [`fusion::MIN_POINTS`].
    TooFewPoints,
    /// Too few points land on walls at the result.
    PoorFit,
    /// The map has no wall information in reach (nothing constrains).
    Unconstrained,
    /// The map is larger than the matcher's coarse levels hold.
    MapTooLarge,
}

/// The result of one refinement.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Match {
    /// The matched pose.
    pub pose: PoseU,
    /// Points that land on a wall (interpolated wall value ≥ ½).
    pub inliers: u32,
    /// Points used.
    pub points: u32,
    /// The translational information, its smaller eigenvalue (Q16 per
    /// 5 cm cell²) and the larger one's direction (a unit vector, Q14).
    pub info_min: i64,
    /// The larger eigenvalue of the translational information.
    pub info_max: i64,
    /// Direction of the better-constrained axis, Q14.
    pub strong_axis_q14: (i32, i32),
    /// Heading information (Q16 per rad², from the normal matrix).
    pub info_theta: i64,
}

/// The matcher's buffers: the scan points and the coarse levels, sized by
/// the words `MW` of the levels' bitsets. `MW` ≥ [`matcher_words`] of the
/// evidence map's size.
pub struct ScanMatcher<const MW: usize> {
    /// The de-skewed points of the latest revolution.
    pub points: ScanPoints,
    /// The coarse wall levels.
    pub pyramid: Pyramid<MW>,
    /// The floor the body swept last ([`trail`]).
    pub trail: trail::Trail,
}

impl<const MW: usize> Default for ScanMatcher<MW> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const MW: usize> ScanMatcher<MW> {
    /// Empty buffers.
    pub const fn new() -> Self {
        Self {
            points: ScanPoints::new(),
            pyramid: Pyramid::new(),
            trail: trail::Trail::new(),
        }
    }
}

/// Words the coarse levels of a `width × height` evidence map need (4
/// bits a block).
pub const fn matcher_words(width: usize, height: usize) -> usize {
    let mut total = 0;
    let mut k = 1;
    while k <= LEVELS {
        let s = 1 << k;
        total += width.div_ceil(s) * height.div_ceil(s);
        k += 1;
    }
    total.div_ceil(8)
}
