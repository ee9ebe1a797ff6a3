//! The numbers of the paper and of module 1's assumed geometry, in one place.
//!
//! Every named constructor of the crate takes its numbers from here:
//! [`Pose::paper_start`](crate::Pose::paper_start),
//! [`TipTargets::paper`](crate::TipTargets::paper),
//! [`InstrumentGeometry::paper`](crate::InstrumentGeometry::paper) and
//! [`Instrument::paper`](crate::Instrument::paper), the default
//! [`JointLimits`](crate::JointLimits),
//! [`ParallelGeometry::assumed`](crate::ParallelGeometry::assumed) and
//! [`SymmetricLayout::assumed`](crate::SymmetricLayout::assumed),
//! [`RobotGeometry::paper`](crate::RobotGeometry::paper) and
//! [`Controller::paper`](crate::Controller::paper).
//!
//! The values are in the units people write them in (mm and degrees), as
//! `f64`; the constructors convert them to the crate's units (mm, rad) and
//! float type. Where they come from: see `docs/model.md`, *Check values*
//! (the paper's start pose and tips), *Instrument modules* (the instrument
//! geometry and the assumed joint limits) and *Module 1, the parallel robot*
//! (the assumed geometry).

// ------------------------------------------------------------ the paper

/// The paper's start pose `P0 = (X_P, Y_P, Z_P, psi, theta, phi)`: mm for
/// the position, degrees for the Euler angles.
pub const START_POSE_MM_DEG: [f64; 6] = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];

/// The left instrument's tip in the paper, mm, fixed frame. The paper gives
/// no right tip: see [`RIGHT_TIP_SHIFT_MM`].
pub const LEFT_TIP_MM: [f64; 3] = [50.0, -50.0, -620.0];

/// The default right tip (**assumed**: the paper gives none) is the left
/// tip's mirror image across the platform's `Y'Z'` plane at the start pose,
/// moved by this vector in the platform frame, mm: 35 mm along `X'` (back
/// towards its own port) and 100 mm along `Y'`. The mirror itself makes the
/// two shafts intersect; moved so, with the assumed bodies
/// ([`BODIES_MM`]), the right shaft clears the left one and the endoscope
/// by more than 2 mm over the paper's whole turn (`docs/model.md`,
/// *The paper's scenario*).
pub const RIGHT_TIP_SHIFT_MM: [f64; 3] = [35.0, 100.0, 0.0];

/// `alpha`, the tilt of an instrument module's first joint axis, deg.
pub const INSTRUMENT_ALPHA_DEG: f64 = 10.0;

/// `beta`, the angle between the tool and the second joint's plane, deg.
pub const INSTRUMENT_BETA_DEG: f64 = 10.0;

/// `R`, the radius of an instrument module's spherical linkage, mm.
pub const INSTRUMENT_RADIUS_MM: f64 = 110.0;

/// The left module's RCM (port) in the platform frame, mm; the right one is
/// its mirror image `(10, 0, 0)` mm.
pub const LEFT_RCM_MM: [f64; 3] = [-10.0, 0.0, 0.0];

// ------------------------------------- assumed: the paper gives none

/// The default limits of `qs1`, deg (**assumed**).
pub const QS1_LIMITS_DEG: [f64; 2] = [-120.0, 120.0];

/// The default limits of `qs2`, deg (**assumed**; they exclude assembly mode B).
pub const QS2_LIMITS_DEG: [f64; 2] = [-80.0, 80.0];

/// The default limits of `qs3`, mm (**assumed**).
pub const QS3_LIMITS_MM: [f64; 2] = [10.0, 300.0];

/// The endoscope's insertion depth range, mm: 0 at its port (the platform's
/// origin `P`), positive inwards. **Assumed**: the paper gives no number.
pub const ENDOSCOPE_DEPTH_MM: [f64; 2] = [0.0, 250.0];

/// The bodies as capsules, mm: each instrument shaft's diameter and
/// length, the endoscope's diameter and length. **Assumed** (typical
/// laparoscopic sizes): the paper gives none.
pub const BODIES_MM: [f64; 4] = [5.0, 400.0, 10.0, 400.0];

/// Module 1's **assumed** geometry: a plausible robot of the right family,
/// not the real PARA-SILSROB, whose dimensions are not published.
///
/// Three legs with a 120-degree symmetry (see
/// [`SymmetricLayout`](crate::SymmetricLayout) for the meaning of each number).
pub mod module1 {
    /// `gamma_i`, the azimuth of each leg about `Z`, deg.
    pub const LEG_AZIMUTHS_DEG: [f64; 3] = [90.0, 210.0, 330.0];
    /// `R_b`, the radius of each leg's guide-pair centre, mm.
    pub const BASE_RADIUS_MM: f64 = 200.0;
    /// `w`, the half-spacing of a leg's two guides, mm.
    pub const HALF_SPACING_MM: f64 = 160.0;
    /// The direction of every guide, fixed frame: straight down from `Z = 0`.
    pub const GUIDE_DIRECTION: [f64; 3] = [0.0, 0.0, -1.0];
    /// `l_j`, every link's length, mm.
    pub const LINK_LENGTH_MM: f64 = 350.0;
    /// The stroke of every slider, mm.
    pub const STROKE_MM: [f64; 2] = [0.0, 320.0];
    /// `r_p`, the radius of the platform nodes about `z'`, mm.
    pub const NODE_RADIUS_MM: f64 = 150.0;
    /// `h`, the height of the nodes above `P` along `+z'`, mm.
    pub const NODE_HEIGHT_MM: f64 = 100.0;
    /// The azimuth of node `i` in the platform frame minus `gamma_i`, deg.
    pub const NODE_AZIMUTH_OFFSET_DEG: f64 = 60.0;
}
