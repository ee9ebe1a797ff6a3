//! The paper's reorientation as a smooth motion with analytic rates.

// Each test binary uses its own part of the shared modules.
#![allow(dead_code)]

use parasils_kin::{PlatformState, Pose, Real};

/// The smooth stand-in for the paper's reorientation (`docs/model.md`,
/// *Check values*, the increments reading): `psi: -15 -> 0 deg`, `theta: 10 -> 35 deg` over 4.5 s
/// with a quintic smoothstep, `P` and `phi` still; rates analytic.
pub fn reorientation<T: Real>(t: f64) -> PlatformState<T> {
    let duration = 4.5;
    let s = (t / duration).clamp(0.0, 1.0);
    let pos = s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
    let vel = 30.0 * s * s * (1.0 - s) * (1.0 - s) / duration;
    let acc = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (duration * duration);
    let (d_psi, d_theta) = (15f64.to_radians(), 25f64.to_radians());
    let mut pose = Pose::paper_start().to_array();
    pose[3] += d_psi * pos;
    pose[4] += d_theta * pos;
    PlatformState::reorientation(
        Pose::from_array(pose.map(T::lit)),
        [T::lit(d_psi * vel), T::lit(d_theta * vel)],
        [T::lit(d_psi * acc), T::lit(d_theta * acc)],
    )
}
