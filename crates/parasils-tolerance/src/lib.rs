//! Tolerance analysis of PARA-SILSROB: with the tolerances a shop can
//! machine and assemble, how far do the instrument tips really move during a
//! motion when the controller drives the nominal model?
//!
//! A [`Study`] takes the controller's nominal commands along a motion (a
//! [`Trace`]: module 1's six actuators and both modules' joints at every
//! sample), draws perturbed robots from a [`Spec`] (one distribution per
//! parameter family, named like the robot file's keys), and replays the
//! commands on each ([`ReplayPlan::replay`]): module 1's forward kinematics
//! by the chord method from the nominal robot's Jacobian at the same sample
//! (the reference, [`replay()`], solves it by Newton's method from the
//! previous pose), then each instrument's forward kinematics with its own
//! perturbed parameters. Per robot, the result is the largest deviation of
//! each tip from the commanded one and of the platform from its commanded
//! pose. Sample `i`'s robot depends only on the seed and `i`
//! ([`Perturbation::draw`]), so a study splits over threads, processes or
//! machines in any way and gives the same numbers bit for bit.
//!
//! [`Linearisation`] is the same error to first order, from analytic
//! derivatives: the small-tolerance check of the Monte Carlo, and the
//! [`Sensitivity`] ranking of the families. [`Report`] gathers the
//! percentiles, the histogram and the ranking a designer reads.
//!
//! ```
//! use parasils_sim::Scenario;
//! use parasils_tolerance::{Report, Spec, Study, Trace};
//!
//! // The paper's reorientation at 10 Hz, 64 perturbed robots.
//! let mut scenario = Scenario::paper();
//! scenario.rate_hz = 10.0;
//! let study = Study::new(Spec::default(), Trace::from_scenario(scenario)?, 0)?;
//! let results = study.run(0..64, 2, &|_| true)?;
//! let report = Report::new(&results, Some(&study.linearisation()?), study.spec());
//! assert_eq!(report.failed, 0);
//! // The default tolerances move the tips by tenths of a millimetre.
//! let p50 = report.tip.percentiles[0].1;
//! assert!(p50 > 0.02 && p50 < 1.0, "{p50}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Modules
//! | module | concept |
//! |---|---|
//! | [`spec`] | the tolerance specification (TOML or JSON) |
//! | [`perturbation`] | one perturbed robot, from a counter-based generator |
//! | [`trace`] | the nominal commands along a motion |
//! | [`replay`](mod@replay) | the commands replayed on a perturbed robot: its model error (the reference by Newton, the study's plan by the chord method) |
//! | [`linear`] | the first-order model and the sensitivity ranking |
//! | [`study`] | a study and its threaded runs |
//! | [`report`] | percentiles, histogram, ranking |
//! | [`output`] | the results as CSV or Parquet, written atomically |
//! | `plot` | the histogram as a picture (feature `plot`) |

pub mod linear;
pub mod output;
pub mod perturbation;
#[cfg(feature = "plot")]
pub mod plot;
pub mod replay;
pub mod report;
pub mod spec;
pub mod study;
pub mod trace;

pub use linear::{LinearError, Linearisation, Sensitivity};
pub use output::TableFormat;
pub use perturbation::{InstrumentDeviation, Perturbation};
pub use replay::{Deviation, ReplayFailure, ReplayPlan, replay};
pub use report::{Histogram, Report, Stats};
pub use spec::{Distribution, Family, Spec, SpecError};
pub use study::{Interrupted, Results, Study, StudyError};
pub use trace::{Command, Trace};
