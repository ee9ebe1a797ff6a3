//! Calibration of PARA-SILSROB's module 1, the 6-DOF parallel robot: its
//! real geometry identified from the actuator readings at measured platform
//! poses (see `docs/model.md`, *Calibration*).
//!
//! The residual is the inverse kinematics' `q_measured - q_ik(pose; x)`,
//! closed-form with its derivatives ([`model`]) over the 51 parameters of
//! [`params`] (per actuator the guide point, direction, link length and
//! encoder offset; per leg the node). [`identify`] fixes what the data
//! cannot see, [`fit`] runs Levenberg-Marquardt and reports standard
//! deviations and observability, and [`plan`] chooses the poses to measure.
//! Every public type is also at the crate root.
//!
//! ```
//! use parasils_calib::{FitOptions, Measurement, Sigma, calibrate, plan};
//! use parasils_kin::{ParallelGeometry, ParallelRobot, Pose};
//!
//! let nominal = ParallelGeometry::<f64>::assumed();
//! // The "real" robot: one link 0.5 mm longer, one encoder 1 mm off.
//! let mut real = nominal;
//! real.guides[2].link_length += 0.5;
//! real.guides[4].encoder_offset = 1.0;
//! let real = ParallelRobot::new(real)?;
//! let options = plan::PlanOptions { poses: 30, candidates: 300, ..Default::default() };
//! let poses = plan::plan(&nominal, &options)?.poses;
//! let data: Vec<Measurement> = poses
//!     .iter()
//!     .map(|&p| {
//!         let [x, y, z, a, b, c] = p;
//!         let q = real.ik(&Pose::from_mm_deg(x, y, z, a, b, c)).expect("in reach");
//!         Measurement { q_mm: q.0, pose: p, sigma: Sigma::default() }
//!     })
//!     .collect();
//! let fit = calibrate(&nominal, &data, &FitOptions::default())?;
//! assert!((fit.geometry.guides[2].link_length - 350.5).abs() < 1e-8);
//! assert!((fit.geometry.guides[4].encoder_offset - 1.0).abs() < 1e-8);
//! assert!(fit.report.rms_after_mm < 1e-9);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod data;
pub mod error;
pub mod fit;
pub mod identify;
pub mod model;
pub mod params;
pub mod plan;
pub mod report;

pub use data::{Measurement, Sigma};
pub use error::CalibError;
pub use fit::{Fit, FitOptions, calibrate};
pub use identify::{Fixed, Selection};
pub use model::{Model, OutOfReach, PoseEval, PoseMmDeg};
pub use params::{PARAMETERS, Parameter, ParameterMap};
pub use plan::{Plan, PlanOptions, PlanReport};
pub use report::{FixedParameter, Identified, Observability, Outcome, Report, Worst};
