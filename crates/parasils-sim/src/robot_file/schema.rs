//! The robot file's tables as serde reads and writes them (keys with their
//! units, degrees in the file), and their conversions to and from the
//! kinematics' geometry (radians in memory).

use nalgebra::Vector3;
use parasils::kin::limits;
use parasils::kin::{
    ActuatorLimits, BodyGeometry, Branch, Calibration, Camera, EndoscopeGeometry, FkOptions, Guide,
    InstrumentGeometry, Interval, JointLimits, ParallelGeometry, ParallelThresholds, RobotGeometry,
    Side, Thresholds,
};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::dynamics::{DynamicsFile, StiffnessFile};
use crate::supervisor::SupervisorTable;

/// The whole robot as the file holds it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotFile {
    /// Module 1, the parallel robot.
    pub module1: Module1File,
    /// The left instrument module.
    pub left: InstrumentFile,
    /// The right instrument module.
    pub right: InstrumentFile,
    /// `[endoscope]`: its insertion depth's range (default `[0, 250]` mm,
    /// assumed, when the table is missing).
    #[serde(default = "EndoscopeFile::paper")]
    pub endoscope: EndoscopeFile,
    /// `[camera]`: the endoscope's camera (see [`CameraFile`]); missing,
    /// the assumed straight 70 deg, 16:9 scope, and written only when it
    /// differs from that.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraFile>,
    /// `[supervisor]`: the margin supervisor's thresholds (see
    /// [`SupervisorTable`]; not part of the geometry).
    #[serde(default, skip_serializing)]
    pub supervisor: Option<SupervisorTable>,
    /// `[bodies]`: the shafts' and the endoscope's sizes (see
    /// [`BodiesFile`]; not part of the geometry; each key missing keeps its
    /// assumed default).
    #[serde(default, skip_serializing)]
    pub bodies: Option<BodiesFile>,
    /// `[dynamics]`: the platform as one rigid body (see [`DynamicsFile`];
    /// not part of the geometry; missing, no weight and no inertia, and no
    /// force columns without a tip load).
    #[serde(default, skip_serializing)]
    pub dynamics: Option<DynamicsFile>,
    /// `[stiffness]`: each actuator's stiffness (see [`StiffnessFile`]; not
    /// part of the geometry; each key missing keeps its assumed default).
    #[serde(default, skip_serializing)]
    pub stiffness: Option<StiffnessFile>,
}

/// The bodies in the file: `[bodies]`, the instrument shafts and the
/// endoscope as capsules for the clearance checks. Every key is optional;
/// the defaults are **assumed** (the real robot's are not published).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BodiesFile {
    /// Each instrument shaft's diameter, mm (assumed 5).
    #[serde(deserialize_with = "non_negative")]
    pub instrument_diameter_mm: f64,
    /// Each instrument shaft's length from its tip, mm (assumed 400).
    #[serde(deserialize_with = "non_negative")]
    pub instrument_length_mm: f64,
    /// The endoscope's diameter, mm (assumed 10).
    #[serde(deserialize_with = "non_negative")]
    pub endoscope_diameter_mm: f64,
    /// The endoscope's length from its tip, mm (assumed 400).
    #[serde(deserialize_with = "non_negative")]
    pub endoscope_length_mm: f64,
}

impl Default for BodiesFile {
    /// The assumed sizes ([`BodyGeometry::assumed`]).
    fn default() -> Self {
        Self::from_bodies(&BodyGeometry::assumed())
    }
}

impl BodiesFile {
    /// The file's table of `bodies`.
    pub fn from_bodies(bodies: &BodyGeometry<f64>) -> Self {
        Self {
            instrument_diameter_mm: bodies.instrument_diameter,
            instrument_length_mm: bodies.instrument_length,
            endoscope_diameter_mm: bodies.endoscope_diameter,
            endoscope_length_mm: bodies.endoscope_length,
        }
    }

    /// The sizes the table gives.
    pub fn to_bodies(&self) -> BodyGeometry<f64> {
        BodyGeometry {
            instrument_diameter: self.instrument_diameter_mm,
            instrument_length: self.instrument_length_mm,
            endoscope_diameter: self.endoscope_diameter_mm,
            endoscope_length: self.endoscope_length_mm,
        }
    }
}

/// The endoscope in the file: `[endoscope]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EndoscopeFile {
    /// The insertion depth's range `[min, max]`, mm: 0 at the port (the
    /// platform's origin `P`), positive inwards.
    #[serde(deserialize_with = "interval")]
    pub depth_mm: [f64; 2],
}

impl EndoscopeFile {
    fn paper() -> Self {
        let d = EndoscopeGeometry::<f64>::paper().depth;
        Self {
            depth_mm: [d.min, d.max],
        }
    }
}

/// The endoscope's camera in the file: `[camera]`, degrees (every key
/// optional, the assumed scope's value when missing).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraFile {
    /// The horizontal field of view, deg (assumed 70).
    #[serde(default = "CameraFile::hfov")]
    pub horizontal_fov_deg: f64,
    /// Width over height of the image (assumed 16:9).
    #[serde(default = "CameraFile::aspect")]
    pub aspect_ratio: f64,
    /// An oblique scope's tilt from the endoscope's axis, deg (0: straight).
    #[serde(default)]
    pub oblique_deg: f64,
    /// The direction of the tilt from the platform's `X'` axis in its
    /// `X'Y'` plane, deg.
    #[serde(default)]
    pub oblique_direction_deg: f64,
}

impl CameraFile {
    fn hfov() -> f64 {
        Camera::<f64>::assumed().horizontal_fov.to_degrees()
    }

    fn aspect() -> f64 {
        Camera::<f64>::assumed().aspect_ratio
    }

    /// The file's form of `camera`: `None` for the assumed one.
    fn from_camera(camera: &Camera<f64>) -> Option<Self> {
        (*camera != Camera::assumed()).then(|| Self {
            horizontal_fov_deg: to_deg(camera.horizontal_fov),
            aspect_ratio: camera.aspect_ratio,
            oblique_deg: to_deg(camera.oblique),
            oblique_direction_deg: to_deg(camera.oblique_direction),
        })
    }

    /// The camera (degrees to radians), not yet validated.
    fn to_camera(self) -> Camera<f64> {
        Camera {
            horizontal_fov: self.horizontal_fov_deg.to_radians(),
            aspect_ratio: self.aspect_ratio,
            oblique: self.oblique_deg.to_radians(),
            oblique_direction: self.oblique_direction_deg.to_radians(),
        }
    }
}

/// Module 1 in the file: `[module1]`, six `[[module1.guides]]` (`q1` to `q6`
/// in order) and three `[[module1.legs]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Module1File {
    /// Whether the dimensions are assumed (the default geometry) rather than
    /// the real robot's.
    pub assumed: bool,
    /// Smallest accepted serial margin `|e.u| / l`, in `(0, 1)`.
    #[serde(deserialize_with = "positive")]
    pub serial_margin_min: f64,
    /// Smallest parallel margin the forward kinematics accepts.
    #[serde(deserialize_with = "positive")]
    pub parallel_margin_min: f64,
    /// Smallest parallel margin the per-cycle call accepts (a command
    /// closer to a parallel singularity is refused).
    #[serde(deserialize_with = "positive")]
    pub parallel_margin_command_min: f64,
    /// Smallest `|cos theta|` the forward kinematics accepts.
    #[serde(deserialize_with = "positive")]
    pub euler_cos_theta_min: f64,
    /// The forward kinematics' tolerance, relative to the link lengths.
    #[serde(deserialize_with = "positive")]
    pub fk_tolerance_rel: f64,
    /// The forward kinematics' largest number of Newton steps (at least 1).
    #[serde(deserialize_with = "at_least_one")]
    pub fk_max_iterations: u32,
    /// The six actuators' guides, `q1` to `q6`.
    pub guides: [GuideFile; 6],
    /// The three legs' platform nodes, leg 1 (`q1`, `q2`) to leg 3 (`q5`, `q6`).
    pub legs: [LegFile; 3],
    /// `[module1.calibration]`, written by `parasils calibrate`: `poses`, `rms_mm`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<Calibration>,
}

/// One actuator in the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuideFile {
    /// `G_j`, the slider's position at `q_j = 0`, mm, fixed frame.
    #[serde(deserialize_with = "finite3")]
    pub point_mm: [f64; 3],
    /// `u_j`, the direction in which `q_j` grows (normalised on loading).
    #[serde(deserialize_with = "finite3")]
    pub direction: [f64; 3],
    /// `l_j`, the link from slider to node, mm.
    #[serde(deserialize_with = "positive")]
    pub link_length_mm: f64,
    /// `s_j`, `1` or `-1`: which root of the inverse kinematics.
    #[serde(deserialize_with = "branch_sign", serialize_with = "branch_sign_out")]
    pub branch: Branch,
    /// The slider's stroke `[min, max]`, mm, on the reading.
    #[serde(deserialize_with = "interval")]
    pub stroke_mm: [f64; 2],
    /// `o_j`, the reading minus the slider's position along the guide, mm (absent: 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub encoder_offset_mm: Option<f64>,
    /// The slider's velocity limit, mm/s (default assumed 50).
    #[serde(default = "limit_slider_v", deserialize_with = "positive")]
    pub velocity_max_mm_s: f64,
    /// The slider's acceleration limit, mm/s^2 (default assumed 100).
    #[serde(default = "limit_slider_a", deserialize_with = "positive")]
    pub acceleration_max_mm_s2: f64,
    /// The slider's force limit, N (default assumed 200).
    #[serde(default = "limit_slider_f", deserialize_with = "positive")]
    pub force_max_n: f64,
}

/// One leg in the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LegFile {
    /// `a_i`, the spherical-joint centre, mm, platform frame.
    #[serde(deserialize_with = "finite3")]
    pub node_mm: [f64; 3],
}

/// An instrument module in the file: `[left]` or `[right]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstrumentFile {
    /// `alpha`, deg.
    #[serde(deserialize_with = "finite")]
    pub alpha_deg: f64,
    /// `beta`, deg, in `[0, 90)`.
    #[serde(deserialize_with = "finite")]
    pub beta_deg: f64,
    /// The spherical linkage's radius, mm.
    #[serde(deserialize_with = "positive")]
    pub radius_mm: f64,
    /// The port (RCM), mm, platform frame.
    #[serde(deserialize_with = "finite3")]
    pub rcm_mm: [f64; 3],
    /// `qs1` limits `[min, max]`, deg.
    #[serde(deserialize_with = "interval")]
    pub qs1_deg: [f64; 2],
    /// `qs2` limits `[min, max]`, deg.
    #[serde(deserialize_with = "interval")]
    pub qs2_deg: [f64; 2],
    /// `qs3` limits `[min, max]`, mm.
    #[serde(deserialize_with = "interval")]
    pub qs3_mm: [f64; 2],
    /// Relative tolerance of the reach test.
    #[serde(deserialize_with = "positive")]
    pub reach_tolerance_rel: f64,
    /// Smallest accepted `|cos qs2|`.
    #[serde(deserialize_with = "positive")]
    pub cos_qs2_min: f64,
    /// Smallest accepted `qs3`, mm.
    #[serde(deserialize_with = "positive")]
    pub qs3_min_mm: f64,
    /// `qs1`'s velocity limit, deg/s (default assumed 30).
    #[serde(default = "limit_qs12_v", deserialize_with = "positive")]
    pub qs1_velocity_max_deg_s: f64,
    /// `qs2`'s velocity limit, deg/s (default assumed 30).
    #[serde(default = "limit_qs12_v", deserialize_with = "positive")]
    pub qs2_velocity_max_deg_s: f64,
    /// `qs3`'s velocity limit, mm/s (default assumed 60).
    #[serde(default = "limit_qs3_v", deserialize_with = "positive")]
    pub qs3_velocity_max_mm_s: f64,
    /// `qs1`'s acceleration limit, deg/s^2 (default assumed 60).
    #[serde(default = "limit_qs12_a", deserialize_with = "positive")]
    pub qs1_acceleration_max_deg_s2: f64,
    /// `qs2`'s acceleration limit, deg/s^2 (default assumed 60).
    #[serde(default = "limit_qs12_a", deserialize_with = "positive")]
    pub qs2_acceleration_max_deg_s2: f64,
    /// `qs3`'s acceleration limit, mm/s^2 (default assumed 60).
    #[serde(default = "limit_qs3_a", deserialize_with = "positive")]
    pub qs3_acceleration_max_mm_s2: f64,
    /// `qs1`'s torque limit, N mm (default assumed 3000).
    #[serde(default = "limit_qs12_t", deserialize_with = "positive")]
    pub qs1_torque_max_nmm: f64,
    /// `qs2`'s torque limit, N mm (default assumed 3000).
    #[serde(default = "limit_qs12_t", deserialize_with = "positive")]
    pub qs2_torque_max_nmm: f64,
    /// `qs3`'s force limit, N (default assumed 40).
    #[serde(default = "limit_qs3_f", deserialize_with = "positive")]
    pub qs3_force_max_n: f64,
}

fn limit_slider_v() -> f64 {
    limits::SLIDER_VELOCITY_MAX_MM_S
}
fn limit_slider_a() -> f64 {
    limits::SLIDER_ACCELERATION_MAX_MM_S2
}
fn limit_qs12_v() -> f64 {
    limits::QS12_VELOCITY_MAX_DEG_S
}
fn limit_qs12_a() -> f64 {
    limits::QS12_ACCELERATION_MAX_DEG_S2
}
fn limit_qs3_v() -> f64 {
    limits::QS3_VELOCITY_MAX_MM_S
}
fn limit_qs3_a() -> f64 {
    limits::QS3_ACCELERATION_MAX_MM_S2
}
fn limit_slider_f() -> f64 {
    limits::SLIDER_FORCE_MAX_N
}
fn limit_qs12_t() -> f64 {
    limits::QS12_TORQUE_MAX_NMM
}
fn limit_qs3_f() -> f64 {
    limits::QS3_FORCE_MAX_N
}

fn finite<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let v = f64::deserialize(d)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(serde::de::Error::custom(format!(
            "expected a finite number, got {v}"
        )))
    }
}

fn positive<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let v = f64::deserialize(d)?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(serde::de::Error::custom(format!(
            "expected a finite number > 0, got {v}"
        )))
    }
}

fn non_negative<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let v = f64::deserialize(d)?;
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(serde::de::Error::custom(format!(
            "expected a finite number >= 0, got {v}"
        )))
    }
}

fn at_least_one<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let v = u32::deserialize(d)?;
    if v >= 1 {
        Ok(v)
    } else {
        Err(serde::de::Error::custom("expected at least 1, got 0"))
    }
}

fn finite3<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    let v = <[f64; 3]>::deserialize(d)?;
    if v.iter().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(serde::de::Error::custom(format!(
            "expected three finite numbers, got {v:?}"
        )))
    }
}

fn interval<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let v = <[f64; 2]>::deserialize(d)?;
    if v[0] <= v[1] {
        Ok(v)
    } else {
        Err(serde::de::Error::custom(format!(
            "expected an interval [min, max] with min <= max (either may be inf), got {v:?}"
        )))
    }
}

fn branch_sign<'de, D: Deserializer<'de>>(d: D) -> Result<Branch, D::Error> {
    let v = i64::deserialize(d)?;
    Branch::from_sign(v)
        .ok_or_else(|| serde::de::Error::custom(format!("expected 1 or -1, got {v}")))
}

fn branch_sign_out<S: Serializer>(b: &Branch, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_i64(b.as_i64())
}

/// Degrees for the file, chosen so that reading them back gives `rad`
/// exactly when some decimal of degrees does: the shortest of a few
/// roundings that converts back bit for bit (`10` rather than
/// `9.999999999999998`), else the nearest that does. Not every `f64` of
/// radians is the conversion of an `f64` of degrees (about one in ten is
/// not); those read back within one unit in the last place.
fn to_deg(rad: f64) -> f64 {
    let d = rad.to_degrees();
    let back = |x: f64| x.to_radians().to_bits() == rad.to_bits();
    for digits in [6, 9, 12] {
        let k = 10f64.powi(digits);
        let r = (d * k).round() / k;
        if back(r) {
            return r;
        }
    }
    [d, d.next_up(), d.next_down()]
        .into_iter()
        .find(|&x| back(x))
        .unwrap_or(d)
}

fn deg_interval(i: &Interval<f64>) -> [f64; 2] {
    [to_deg(i.min), to_deg(i.max)]
}

fn rad_interval(v: [f64; 2]) -> Interval<f64> {
    Interval::new(v[0].to_radians(), v[1].to_radians())
}

fn mm_interval(v: [f64; 2]) -> Interval<f64> {
    Interval::new(v[0], v[1])
}

impl RobotFile {
    /// The twelve actuators' limits the file gives, library units.
    fn limits(&self) -> ActuatorLimits<f64> {
        let mut out = ActuatorLimits::assumed();
        for (j, g) in self.module1.guides.iter().enumerate() {
            out.velocity[j] = g.velocity_max_mm_s;
            out.acceleration[j] = g.acceleration_max_mm_s2;
            out.force[j] = g.force_max_n;
        }
        for (base, m) in [(6, &self.left), (9, &self.right)] {
            let [v, a, f] = m.limits();
            out.velocity[base..base + 3].copy_from_slice(&v);
            out.acceleration[base..base + 3].copy_from_slice(&a);
            out.force[base..base + 3].copy_from_slice(&f);
        }
        out
    }

    /// The file's form of a geometry (radians to degrees).
    pub fn from_geometry(g: &RobotGeometry<f64>) -> Self {
        let mut file = Self::from_geometry_without_limits(g);
        let l = &g.limits;
        for (j, guide) in file.module1.guides.iter_mut().enumerate() {
            guide.velocity_max_mm_s = l.velocity[j];
            guide.acceleration_max_mm_s2 = l.acceleration[j];
            guide.force_max_n = l.force[j];
        }
        for (base, m) in [(6, &mut file.left), (9, &mut file.right)] {
            let pick = |x: &[f64; 12]| [x[base], x[base + 1], x[base + 2]];
            m.set_limits([pick(&l.velocity), pick(&l.acceleration), pick(&l.force)]);
        }
        file
    }

    fn from_geometry_without_limits(g: &RobotGeometry<f64>) -> Self {
        let m = &g.module1;
        Self {
            module1: Module1File {
                assumed: m.assumed,
                serial_margin_min: m.thresholds.serial,
                parallel_margin_min: m.thresholds.parallel,
                parallel_margin_command_min: m.thresholds.parallel_command,
                euler_cos_theta_min: m.thresholds.euler,
                fk_tolerance_rel: m.fk.tolerance,
                fk_max_iterations: m.fk.max_iterations,
                guides: m.guides.map(|g| GuideFile {
                    point_mm: g.point.into(),
                    direction: g.direction.into(),
                    link_length_mm: g.link_length,
                    branch: g.branch,
                    stroke_mm: [g.stroke.min, g.stroke.max],
                    encoder_offset_mm: (g.encoder_offset != 0.0).then_some(g.encoder_offset),
                    velocity_max_mm_s: limit_slider_v(),
                    acceleration_max_mm_s2: limit_slider_a(),
                    force_max_n: limit_slider_f(),
                }),
                legs: m.nodes.map(|a| LegFile { node_mm: a.into() }),
                calibration: m.calibration,
            },
            left: InstrumentFile::from_geometry(&g.left),
            right: InstrumentFile::from_geometry(&g.right),
            endoscope: EndoscopeFile {
                depth_mm: [g.endoscope.depth.min, g.endoscope.depth.max],
            },
            camera: CameraFile::from_camera(&g.endoscope.camera),
            supervisor: None,
            bodies: None,
            dynamics: None,
            stiffness: None,
        }
    }

    /// The geometry (degrees to radians), not yet validated (see
    /// [`RobotGeometry::validate`]).
    pub fn to_geometry(&self) -> RobotGeometry<f64> {
        let m = &self.module1;
        RobotGeometry {
            module1: ParallelGeometry {
                assumed: m.assumed,
                calibration: m.calibration,
                guides: m.guides.clone().map(|g| Guide {
                    point: Vector3::from(g.point_mm),
                    direction: Vector3::from(g.direction),
                    link_length: g.link_length_mm,
                    branch: g.branch,
                    stroke: mm_interval(g.stroke_mm),
                    encoder_offset: g.encoder_offset_mm.unwrap_or(0.0),
                }),
                nodes: m.legs.clone().map(|l| Vector3::from(l.node_mm)),
                thresholds: ParallelThresholds {
                    serial: m.serial_margin_min,
                    parallel: m.parallel_margin_min,
                    parallel_command: m.parallel_margin_command_min,
                    euler: m.euler_cos_theta_min,
                },
                fk: FkOptions {
                    tolerance: m.fk_tolerance_rel,
                    max_iterations: m.fk_max_iterations,
                },
            },
            left: self.left.to_geometry(Side::Left),
            right: self.right.to_geometry(Side::Right),
            endoscope: EndoscopeGeometry {
                depth: mm_interval(self.endoscope.depth_mm),
                camera: self.camera.map_or_else(Camera::assumed, |c| c.to_camera()),
            },
            limits: self.limits(),
        }
    }
}

impl InstrumentFile {
    /// The file's form of an instrument module (radians to degrees).
    pub fn from_geometry(g: &InstrumentGeometry<f64>) -> Self {
        Self {
            alpha_deg: to_deg(g.alpha),
            beta_deg: to_deg(g.beta),
            radius_mm: g.radius,
            rcm_mm: g.rcm.into(),
            qs1_deg: deg_interval(&g.limits.qs1),
            qs2_deg: deg_interval(&g.limits.qs2),
            qs3_mm: [g.limits.qs3.min, g.limits.qs3.max],
            reach_tolerance_rel: g.thresholds.reach,
            cos_qs2_min: g.thresholds.cos_qs2,
            qs3_min_mm: g.thresholds.qs3,
            qs1_velocity_max_deg_s: limit_qs12_v(),
            qs2_velocity_max_deg_s: limit_qs12_v(),
            qs3_velocity_max_mm_s: limit_qs3_v(),
            qs1_acceleration_max_deg_s2: limit_qs12_a(),
            qs2_acceleration_max_deg_s2: limit_qs12_a(),
            qs3_acceleration_max_mm_s2: limit_qs3_a(),
            qs1_torque_max_nmm: limit_qs12_t(),
            qs2_torque_max_nmm: limit_qs12_t(),
            qs3_force_max_n: limit_qs3_f(),
        }
    }

    /// The file's limits of this module, `[qs1, qs2, qs3]`, velocity,
    /// acceleration, then force, in library units (rad and mm; N mm and N).
    fn limits(&self) -> [[f64; 3]; 3] {
        [
            [
                self.qs1_velocity_max_deg_s.to_radians(),
                self.qs2_velocity_max_deg_s.to_radians(),
                self.qs3_velocity_max_mm_s,
            ],
            [
                self.qs1_acceleration_max_deg_s2.to_radians(),
                self.qs2_acceleration_max_deg_s2.to_radians(),
                self.qs3_acceleration_max_mm_s2,
            ],
            [
                self.qs1_torque_max_nmm,
                self.qs2_torque_max_nmm,
                self.qs3_force_max_n,
            ],
        ]
    }

    /// Sets this module's limits from library units (`[qs1, qs2, qs3]`,
    /// velocity, acceleration, then force).
    fn set_limits(&mut self, [v, a, f]: [[f64; 3]; 3]) {
        self.qs1_velocity_max_deg_s = to_deg(v[0]);
        self.qs2_velocity_max_deg_s = to_deg(v[1]);
        self.qs3_velocity_max_mm_s = v[2];
        self.qs1_acceleration_max_deg_s2 = to_deg(a[0]);
        self.qs2_acceleration_max_deg_s2 = to_deg(a[1]);
        self.qs3_acceleration_max_mm_s2 = a[2];
        [
            self.qs1_torque_max_nmm,
            self.qs2_torque_max_nmm,
            self.qs3_force_max_n,
        ] = f;
    }

    /// The module on `side` (degrees to radians), not yet validated.
    pub fn to_geometry(&self, side: Side) -> InstrumentGeometry<f64> {
        InstrumentGeometry {
            side,
            alpha: self.alpha_deg.to_radians(),
            beta: self.beta_deg.to_radians(),
            radius: self.radius_mm,
            rcm: Vector3::from(self.rcm_mm),
            limits: JointLimits {
                qs1: rad_interval(self.qs1_deg),
                qs2: rad_interval(self.qs2_deg),
                qs3: mm_interval(self.qs3_mm),
            },
            thresholds: Thresholds {
                reach: self.reach_tolerance_rel,
                cos_qs2: self.cos_qs2_min,
                qs3: self.qs3_min_mm,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degrees_read_back_exactly() {
        for d in [10.0f64, -120.0, 80.0, 0.1, 33.333, 1e-7, 12.345_678_901] {
            let r = d.to_radians();
            assert_eq!(to_deg(r).to_radians().to_bits(), r.to_bits(), "{d}");
        }
        assert_eq!(to_deg(10f64.to_radians()).to_bits(), 10f64.to_bits());
        assert_eq!(to_deg(f64::INFINITY).to_bits(), f64::INFINITY.to_bits());
        // Any angle reads back within one unit in the last place.
        for k in 0..10_000 {
            let r = 0.123_456_789 + f64::from(k) * 1.234_567e-4;
            let back = to_deg(r).to_radians();
            assert!((back - r).abs() <= r.abs() * f64::EPSILON, "{r}");
        }
    }
}
