#![doc = include_str!("../README.md")]
//!
//! # This crate
//!
//! `parasils` is the facade over [`parasils_kin`] (as [`kin`]) and
//! [`parasils_traj`] (as [`traj`]), and the bridge between them:
//! [`Reorientation`] turns a synchronised profile into the
//! [`PlatformState`](kin::PlatformState)s the controller steps through, and
//! [`paper`] states the paper's scenario once; [`OnlineController`] is the
//! per-cycle loop that accepts new goals and stops while the platform moves,
//! watched by a margin [`Supervisor`]; [`teleop`] is the console's
//! per-cycle core (hands and camera to the twelve setpoints). `#![no_std]`, allocation-free,
//! generic over `f32`/`f64` ([`Real`]). The README above is this crate's
//! documentation, so its Rust examples run as doc-tests.
#![no_std]

pub use parasils_kin as kin;
pub use parasils_traj as traj;

pub mod cycle;
mod error;
pub mod follow;
pub mod geometry;
pub mod margin;
pub mod motions;
pub mod online;
pub mod paper;
pub mod path;
pub mod regions;
pub mod reorientation;
pub mod supervisor;
pub mod teleop;

pub use cycle::{OnCycle, Stretch, TimeScaled};
pub use error::Error;
pub use follow::{Follow, FollowError, FollowParams, FollowPhase, FollowStep};
pub use geometry::{Geometry, MotionSample, MotionType, Moving, Port, RobotState};
pub use margin::Margin;
pub use motions::{Insertion, Manipulation, Motion, Positioning, Turning};
pub use online::{
    ClearanceWatch, MAX_TIP_STEP_MM, MotionKind, OnlineController, PROBE_BAND_MM, Setpoint,
};
pub use path::{MotionPath, PathPoint};
pub use regions::{ForbiddenRegions, InBodyCapsules, NearestRegion, NoRegions, RegionQueryError};
pub use reorientation::Reorientation;
pub use supervisor::{
    ClearanceThresholds, ClearanceVerdict, GapVerdict, MarginSet, Margins, PairSet, Supervisor,
    Verdict,
};
pub use teleop::{
    CameraCommand, CameraInput, Command, CommandOutcome, Device, Fault, Goal, HandCommand,
    HandInput, HoldAt, Inputs, LowPass, MoveRefused, OperatingState, Teleop, TeleopCycle,
    TeleopError, TeleopParams, Transition,
};

/// The float type of both crates, [`f32`] or [`f64`]: the one trait the
/// kinematics ([`kin::Real`]) and the profiles ([`traj::Real`]) are both
/// generic over (defined in `parasils-num`).
pub use parasils_kin::Real;
