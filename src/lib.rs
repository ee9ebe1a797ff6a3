//! parasils: kinematics and motion for PARA-SILSROB.
#![no_std]
pub use parasils_kin as kin;
pub use parasils_traj as traj;
