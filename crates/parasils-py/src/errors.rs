//! The Python exceptions: `parasils.KinematicsError` and its subclasses (one
//! per variant of `parasils_kin::Error`, carrying its fields as attributes),
//! `TrajectoryError` and `RobotFileError`, all subclasses of `ValueError`.
//!
//! Values in the attributes are in the libraries' units (mm, rad); the
//! messages are the Rust errors' `Display` texts (degrees for angles).

use std::path::Path;

use parasils_kin::Error;
use parasils_kin::error::{InstrumentSingularity, Joint, ParallelSingularity};
use parasils_sim::robot_file::RobotFileError as FileError;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyType;

pyo3::create_exception!(
    parasils,
    KinematicsError,
    PyValueError,
    "A kinematics solver failed (a subclass of ValueError).\n\n\
     Attributes common to every subclass:\n\n\
     - kind (str): the variant, e.g. 'out_of_reach', 'joint_limit';\n\
     - row (int | None): the index of the first failing row of a batch (or the\n  \
       sample of parasils.simulate); None for a single sample;\n\
     - t (float | None): the time of the failing sample in parasils.simulate, s;\n  \
       None elsewhere.\n\n\
     Each subclass adds the Rust error's fields, in mm and rad."
);
pyo3::create_exception!(
    parasils,
    NonFiniteError,
    KinematicsError,
    "A NaN or infinite input (kind 'non_finite').\n\n\
     Attributes: what (str, the input, e.g. 'pose.psi', 'tip.x'), value (float)."
);
pyo3::create_exception!(
    parasils,
    InvalidParameterError,
    KinematicsError,
    "A geometry parameter out of its valid range (kind 'invalid_parameter').\n\n\
     Attributes: what (str, e.g. 'instrument.beta'), value (float, mm or rad)."
);
pyo3::create_exception!(
    parasils,
    OutOfReachError,
    KinematicsError,
    "The tip asks an instrument module for a direction outside its cone of reach\n\
     (kind 'out_of_reach').\n\n\
     Attributes: side ('left' | 'right'), sin_qs2 (float, |v_x| / cos(beta) > 1)."
);
pyo3::create_exception!(
    parasils,
    SingularError,
    KinematicsError,
    "An instrument module at or next to a singularity (kind 'singular'): |cos qs2|\n\
     or qs3 (the tip at the RCM) below its threshold.\n\n\
     Attributes: side ('left' | 'right'), margin ('cos_qs2' | 'qs3'), value (float,\n\
     dimensionless or mm), threshold (float)."
);
pyo3::create_exception!(
    parasils,
    JointLimitError,
    KinematicsError,
    "An instrument joint beyond its limit (kind 'joint_limit').\n\n\
     Attributes: side ('left' | 'right'), joint ('qs1' | 'qs2' | 'qs3'), value,\n\
     min, max (float, rad for qs1 and qs2, mm for qs3), limit (the bound exceeded)."
);
pyo3::create_exception!(
    parasils,
    LegOutOfReachError,
    KinematicsError,
    "Module 1: a leg cannot reach its platform node at this pose\n\
     (kind 'leg_out_of_reach').\n\n\
     Attributes: actuator (int, 1 to 6), discriminant (float, mm^2, negative)."
);
pyo3::create_exception!(
    parasils,
    ActuatorLimitError,
    KinematicsError,
    "Module 1: an actuator beyond its stroke (kind 'actuator_limit').\n\n\
     Attributes: actuator (int, 1 to 6), value, min, max (float, mm), limit (the\n\
     bound exceeded, mm)."
);
pyo3::create_exception!(
    parasils,
    SerialSingularError,
    KinematicsError,
    "Module 1: a link (nearly) perpendicular to its guide, a serial singularity\n\
     (kind 'serial_singular').\n\n\
     Attributes: actuator (int, 1 to 6), margin (float, |e.u|/l), threshold (float)."
);
pyo3::create_exception!(
    parasils,
    ParallelSingularError,
    KinematicsError,
    "Module 1: the commanded pose is at or next to a parallel (type 2)\n\
     singularity, where the locked actuators do not hold the platform\n\
     (kind 'parallel_singular').\n\n\
     Attributes: margin (float, the parallel margin), threshold (float)."
);
pyo3::create_exception!(
    parasils,
    NoConvergenceError,
    KinematicsError,
    "Module 1 forward kinematics: Newton's method did not converge\n\
     (kind 'no_convergence'). Seed it with a closer guess.\n\n\
     Attributes: iterations (int), residual (float, relative to the link lengths)."
);
pyo3::create_exception!(
    parasils,
    SingularJacobianError,
    KinematicsError,
    "Module 1 forward kinematics: a singular Jacobian at an iterate\n\
     (kind 'singular_jacobian').\n\n\
     Attributes: singularity ('parallel' | 'euler_angles', the Rust field `kind`),\n\
     iteration (int, 0 = the guess), margin (float), threshold (float)."
);
pyo3::create_exception!(
    parasils,
    BranchMismatchError,
    KinematicsError,
    "Module 1 forward kinematics: converged to another assembly mode\n\
     (kind 'branch_mismatch'). Start closer.\n\n\
     Attributes: actuator (int, 1 to 6, the link on the other branch)."
);
pyo3::create_exception!(
    parasils,
    TrajectoryError,
    PyValueError,
    "parasils.simulate: the motion cannot be planned or sampled (a subclass of\n\
     ValueError): a limit or the rate not a positive finite number, a non-finite\n\
     angle, a profile that does not fit the float type.\n\n\
     Attributes: kind (str, e.g. 'invalid_limit', 'invalid_rate'), axis (int | None,\n\
     0 = psi, 1 = theta), value (float | None, in rad, rad/s, rad/s^2 or Hz)."
);
pyo3::create_exception!(
    parasils,
    RobotFileError,
    PyValueError,
    "A robot file (TOML) that cannot be used (a subclass of ValueError): malformed\n\
     TOML, a missing, unknown or mistyped key, a value out of range\n\
     (kind 'parse'), or parameters that do not make a valid robot (kind\n\
     'invalid'; the KinematicsError naming the parameter is its __cause__).\n\n\
     Attributes: kind (str), path (str), line (int | None, 1-based),\n\
     column (int | None, 1-based), key (str | None), text (str | None, the line)."
);

/// Registers every exception type in the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    for t in [
        py.get_type::<KinematicsError>(),
        py.get_type::<NonFiniteError>(),
        py.get_type::<InvalidParameterError>(),
        py.get_type::<OutOfReachError>(),
        py.get_type::<SingularError>(),
        py.get_type::<JointLimitError>(),
        py.get_type::<LegOutOfReachError>(),
        py.get_type::<ActuatorLimitError>(),
        py.get_type::<SerialSingularError>(),
        py.get_type::<ParallelSingularError>(),
        py.get_type::<NoConvergenceError>(),
        py.get_type::<SingularJacobianError>(),
        py.get_type::<BranchMismatchError>(),
        py.get_type::<TrajectoryError>(),
        py.get_type::<RobotFileError>(),
    ] {
        m.add(t.name()?, t)?;
    }
    Ok(())
}

/// An attribute value of an exception.
enum Attr {
    Str(&'static str),
    Float(f64),
    Int(u64),
}

impl<'py> IntoPyObject<'py> for Attr {
    type Target = PyAny;
    type Output = Bound<'py, PyAny>;
    type Error = PyErr;

    fn into_pyobject(self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(match self {
            Attr::Str(s) => s.into_pyobject(py)?.into_any(),
            Attr::Float(v) => v.into_pyobject(py)?.into_any(),
            Attr::Int(v) => v.into_pyobject(py)?.into_any(),
        })
    }
}

/// Builds an exception of type `ty` with `message` and attributes.
fn with_attrs<'py>(
    ty: Bound<'py, PyType>,
    message: String,
    attrs: Vec<(&'static str, Attr)>,
) -> PyResult<PyErr> {
    let value = ty.call1((message,))?;
    for (name, v) in attrs {
        value.setattr(name, v)?;
    }
    Ok(PyErr::from_value(value))
}

fn joint_name(j: Joint) -> &'static str {
    match j {
        Joint::Qs1 => "qs1",
        Joint::Qs2 => "qs2",
        Joint::Qs3 => "qs3",
    }
}

fn margin_name(m: InstrumentSingularity) -> &'static str {
    match m {
        InstrumentSingularity::CosQs2 => "cos_qs2",
        InstrumentSingularity::Qs3 => "qs3",
    }
}

/// The bound that `value` exceeds: `min` below it, `max` otherwise.
fn exceeded(value: f64, min: f64, max: f64) -> f64 {
    if value < min { min } else { max }
}

/// The Python exception for a kinematics error, with `row` (the batch row or
/// simulation sample, `None` for a single call) and `t` (the simulation time).
/// The message starts with `prefix` (`"row 3: "`, `"at t = 1.200 s: "`).
pub(crate) fn kinematics(
    py: Python<'_>,
    error: &Error,
    row: Option<usize>,
    t: Option<f64>,
    prefix: &str,
) -> PyErr {
    let build = || -> PyResult<PyErr> {
        use Attr::{Float, Int, Str};
        let (ty, kind, attrs): (Bound<'_, PyType>, &str, Vec<(&'static str, Attr)>) = match *error {
            Error::NonFinite { what, value } => (
                py.get_type::<NonFiniteError>(),
                "non_finite",
                vec![("what", Str(what)), ("value", Float(value))],
            ),
            Error::InvalidParameter { what, value } => (
                py.get_type::<InvalidParameterError>(),
                "invalid_parameter",
                vec![("what", Str(what)), ("value", Float(value))],
            ),
            Error::OutOfReach { side, sin_qs2 } => (
                py.get_type::<OutOfReachError>(),
                "out_of_reach",
                vec![("side", Str(side.name())), ("sin_qs2", Float(sin_qs2))],
            ),
            Error::Singular {
                side,
                margin,
                value,
                threshold,
            } => (
                py.get_type::<SingularError>(),
                "singular",
                vec![
                    ("side", Str(side.name())),
                    ("margin", Str(margin_name(margin))),
                    ("value", Float(value)),
                    ("threshold", Float(threshold)),
                ],
            ),
            Error::JointLimit {
                side,
                joint,
                value,
                min,
                max,
            } => (
                py.get_type::<JointLimitError>(),
                "joint_limit",
                vec![
                    ("side", Str(side.name())),
                    ("joint", Str(joint_name(joint))),
                    ("value", Float(value)),
                    ("min", Float(min)),
                    ("max", Float(max)),
                    ("limit", Float(exceeded(value, min, max))),
                ],
            ),
            Error::LegOutOfReach {
                actuator,
                discriminant,
            } => (
                py.get_type::<LegOutOfReachError>(),
                "leg_out_of_reach",
                vec![
                    ("actuator", Int(actuator.into())),
                    ("discriminant", Float(discriminant)),
                ],
            ),
            Error::ActuatorLimit {
                actuator,
                value,
                min,
                max,
            } => (
                py.get_type::<ActuatorLimitError>(),
                "actuator_limit",
                vec![
                    ("actuator", Int(actuator.into())),
                    ("value", Float(value)),
                    ("min", Float(min)),
                    ("max", Float(max)),
                    ("limit", Float(exceeded(value, min, max))),
                ],
            ),
            Error::SerialSingular {
                actuator,
                margin,
                threshold,
            } => (
                py.get_type::<SerialSingularError>(),
                "serial_singular",
                vec![
                    ("actuator", Int(actuator.into())),
                    ("margin", Float(margin)),
                    ("threshold", Float(threshold)),
                ],
            ),
            Error::ParallelSingular { margin, threshold } => (
                py.get_type::<ParallelSingularError>(),
                "parallel_singular",
                vec![("margin", Float(margin)), ("threshold", Float(threshold))],
            ),
            Error::NoConvergence {
                iterations,
                residual,
            } => (
                py.get_type::<NoConvergenceError>(),
                "no_convergence",
                vec![
                    ("iterations", Int(iterations.into())),
                    ("residual", Float(residual)),
                ],
            ),
            Error::SingularJacobian {
                kind,
                iteration,
                margin,
                threshold,
            } => (
                py.get_type::<SingularJacobianError>(),
                "singular_jacobian",
                vec![
                    (
                        "singularity",
                        Str(match kind {
                            ParallelSingularity::Parallel => "parallel",
                            ParallelSingularity::EulerAngles => "euler_angles",
                        }),
                    ),
                    ("iteration", Int(iteration.into())),
                    ("margin", Float(margin)),
                    ("threshold", Float(threshold)),
                ],
            ),
            Error::BranchMismatch { actuator } => (
                py.get_type::<BranchMismatchError>(),
                "branch_mismatch",
                vec![("actuator", Int(actuator.into()))],
            ),
            // A variant added to the kinematics after these bindings.
            _ => (py.get_type::<KinematicsError>(), "other", vec![]),
        };
        let err = with_attrs(ty, format!("{prefix}{error}"), attrs)?;
        let value = err.value(py);
        value.setattr("kind", kind)?;
        value.setattr("row", row)?;
        value.setattr("t", t)?;
        Ok(err)
    };
    build().unwrap_or_else(|e| e)
}

/// The Python exception for a trajectory error (`parasils.simulate`).
pub(crate) fn trajectory(py: Python<'_>, error: &parasils_traj::Error) -> PyErr {
    use parasils_traj::Error as E;
    let build = || -> PyResult<PyErr> {
        let (kind, axis, value) = match *error {
            E::InvalidLimit { axis, value, .. } => ("invalid_limit", Some(axis), Some(value)),
            E::NonFinitePosition { axis, value, .. } => {
                ("non_finite_position", Some(axis), Some(value))
            }
            E::DistanceOverflow { axis, goal, .. } => ("distance_overflow", Some(axis), Some(goal)),
            E::OutOfRange { axis, distance } => ("out_of_range", Some(axis), Some(distance)),
            E::InvalidDuration {
                axis, requested, ..
            } => ("invalid_duration", Some(axis), Some(requested)),
            E::InvalidRate { value } => ("invalid_rate", None, Some(value)),
            E::TooManySamples { rate, .. } => ("too_many_samples", None, Some(rate)),
            _ => ("other", None, None),
        };
        let value_obj = py
            .get_type::<TrajectoryError>()
            .call1((format!("trajectory: {error}"),))?;
        value_obj.setattr("kind", kind)?;
        value_obj.setattr("axis", axis)?;
        value_obj.setattr("value", value)?;
        Ok(PyErr::from_value(value_obj))
    };
    build().unwrap_or_else(|e| e)
}

/// Resolves an argument renamed with its unit: `new` (the new name's value,
/// `new_default` when not given) or, when `old` (the old name's value,
/// already converted to the new unit) is given, that one with a
/// `DeprecationWarning`. Both given: `TypeError`.
pub(crate) fn renamed_argument<T: PartialEq>(
    py: Python<'_>,
    method: &str,
    (old_name, old): (&str, Option<T>),
    (new_name, new, new_default): (&str, T, T),
) -> PyResult<T> {
    let Some(old) = old else {
        return Ok(new);
    };
    if new != new_default {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "{method}() got both {new_name} and its deprecated name {old_name}"
        )));
    }
    let message = std::ffi::CString::new(format!(
        "{method}({old_name}=...) is deprecated: use {new_name}=..., in the unit its name \
         says, as the command line's; {old_name} will be removed in the next release"
    ))
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    PyErr::warn(
        py,
        &py.get_type::<pyo3::exceptions::PyDeprecationWarning>(),
        &message,
        1,
    )?;
    Ok(old)
}

/// An `OSError` (its subclass chosen by `errno`, e.g. `FileNotFoundError`)
/// naming `path`.
pub(crate) fn os_error(error: &std::io::Error, path: &Path) -> PyErr {
    match error.raw_os_error() {
        Some(errno) => {
            // Python's own text, without Rust's " (os error N)".
            let text = error.to_string();
            let strerror = text
                .strip_suffix(&format!(" (os error {errno})"))
                .unwrap_or(&text)
                .to_owned();
            PyOSError::new_err((errno, strerror, path.display().to_string()))
        }
        None => PyOSError::new_err(format!("{}: {error}", path.display())),
    }
}

/// The Python exception for a robot file that cannot be used.
pub(crate) fn robot_file(py: Python<'_>, error: &FileError) -> PyErr {
    let build = || -> PyResult<PyErr> {
        let (kind, origin, line, column, key, text, cause) = match error {
            FileError::Io { path, error } => return Ok(os_error(error, path)),
            FileError::Parse {
                origin,
                line,
                column,
                key,
                text,
                ..
            } => ("parse", origin, *line, *column, key, text, None),
            FileError::Invalid {
                origin,
                line,
                key,
                text,
                error,
            } => (
                "invalid",
                origin,
                *line,
                None,
                key,
                text,
                Some(kinematics(py, error, None, None, "")),
            ),
            other => {
                return Ok(RobotFileError::new_err(other.to_string()));
            }
        };
        let value = py
            .get_type::<RobotFileError>()
            .call1((error.to_string(),))?;
        value.setattr("kind", kind)?;
        value.setattr("path", origin.as_ref())?;
        value.setattr("line", line)?;
        value.setattr("column", column)?;
        value.setattr("key", key.as_deref())?;
        value.setattr("text", text.as_deref())?;
        let err = PyErr::from_value(value);
        if let Some(cause) = cause {
            err.set_cause(py, Some(cause));
        }
        Ok(err)
    };
    build().unwrap_or_else(|e| e)
}
