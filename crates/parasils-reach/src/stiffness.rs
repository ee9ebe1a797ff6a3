//! The stiffness measure of a reach map: how far each tip gives way at a
//! feasible cell when it presses on the tissue with a stated force.
//!
//! The measure is the tip's deflection (mm) under a stated tip force, not
//! the smallest eigenvalue of the platform's stiffness `K_x = J^T diag(k) J`:
//! `K_x` mixes N/mm (translation) and N mm/rad (rotation), so its
//! eigenvalues change with the unit of length and name no direction a
//! surgeon sees, and it leaves out the instrument modules' own give. The
//! deflection is in the surgeon's units, at the point that touches the
//! tissue, and sums every spring between the fixed frame and the tip: the
//! six sliders through module 1 (the platform turns about its stiffness
//! centre, carried to the tip by its lever arm) and the module's three
//! joints ([`Controller::tip_deflection`]).

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{ActuatorStiffness, ControlStep, Controller, Side};

/// How far each tip, `[left, right]`, gives way (mm) at `step` when it
/// exerts `load` (N, fixed frame; the tissue pushes back with `-load`), the
/// other tip unloaded, with the actuators springs of `stiffness`; `None`
/// when the kinematics refuse it (a parallel margin below the per-cycle
/// threshold, which a feasible cell never has).
pub fn tip_deflections(
    controller: &Controller<f64>,
    step: &ControlStep<f64>,
    load: &Vector3<f64>,
    stiffness: &ActuatorStiffness<f64>,
) -> Option<[f64; 2]> {
    let of = |side| {
        controller
            .tip_deflection(step, side, &-load, stiffness)
            .ok()
            .map(|d| d.norm())
    };
    Some([of(Side::Left)?, of(Side::Right)?])
}
