//! What the firmware (`f32`, on the MCU) and `build.rs` (`f64`, on the host,
//! for the references) share word for word: how many samples the paper's
//! reorientation has, which of them are compared, and the values of a control
//! step that are compared. The motion itself is
//! [`Reorientation::paper`](parasils::Reorientation::paper), sampled at
//! [`parasils::paper::RATE_HZ`] (see `docs/model.md`, *Check values*).

use parasils::Real;
use parasils::kin::ControlStep;

/// The samples of the motion at [`parasils::paper::RATE_HZ`] (1 kHz):
/// `t = 0, 1 ms, ..., 4.5 s`.
pub const SAMPLE_COUNT: usize = 4501;

/// Every how many samples the firmware compares its `f32` results with the
/// host's `f64` references (indices 0, 250, ..., 4500: 19 samples, among them
/// the profile's switch instants 2000 and 2500).
pub const REFERENCE_EVERY: usize = 250;

/// How many values of a control step are compared, see [`fields`].
pub const FIELD_COUNT: usize = 40;

/// The names of the values of [`fields`], in order (units: mm, rad, s).
pub const FIELD_NAMES: [&str; FIELD_COUNT] = [
    "m1.q1",
    "m1.q2",
    "m1.q3",
    "m1.q4",
    "m1.q5",
    "m1.q6", //
    "m1.q1_dot",
    "m1.q2_dot",
    "m1.q3_dot",
    "m1.q4_dot",
    "m1.q5_dot",
    "m1.q6_dot", //
    "m1.q1_ddot",
    "m1.q2_ddot",
    "m1.q3_ddot",
    "m1.q4_ddot",
    "m1.q5_ddot",
    "m1.q6_ddot", //
    "left.qs1",
    "left.qs2",
    "left.qs3", //
    "left.qs1_dot",
    "left.qs2_dot",
    "left.qs3_dot", //
    "left.qs1_ddot",
    "left.qs2_ddot",
    "left.qs3_ddot", //
    "right.qs1",
    "right.qs2",
    "right.qs3", //
    "right.qs1_dot",
    "right.qs2_dot",
    "right.qs3_dot", //
    "right.qs1_ddot",
    "right.qs2_ddot",
    "right.qs3_ddot", //
    "m1.parallel_margin",
    "m1.serial_margin_min",
    "left.cos_qs2",
    "right.cos_qs2",
];

/// How a field is compared (see `tolerance` in `main.rs`).
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// An angle, rad: absolute tolerance.
    Angle,
    /// A length, mm: absolute tolerance.
    Length,
    /// A rate or an acceleration: tolerance relative to the field's peak
    /// magnitude over the whole motion.
    Rate,
    /// A dimensionless margin: absolute tolerance.
    Margin,
}

/// The kind of each field of [`fields`].
pub const FIELD_KINDS: [Kind; FIELD_COUNT] = {
    use Kind::{Angle as A, Length as L, Margin as M, Rate as R};
    [
        L, L, L, L, L, L, R, R, R, R, R, R, R, R, R, R, R, R, //
        A, A, L, R, R, R, R, R, R, //
        A, A, L, R, R, R, R, R, R, //
        M, M, M, M,
    ]
};

/// The values of one control step that the firmware compares with the
/// host's, in the order of [`FIELD_NAMES`] (`build.rs` checks that there are
/// exactly [`FIELD_COUNT`]).
pub fn values<T: Real>(out: &ControlStep<T>) -> impl Iterator<Item = T> {
    let m1 = &out.module1;
    let (l, r) = (&out.left, &out.right);
    m1.q.0
        .into_iter()
        .chain(m1.q_dot.0)
        .chain(m1.q_ddot.0)
        .chain(l.q.to_array())
        .chain(l.q_dot.to_array())
        .chain(l.q_ddot.to_array())
        .chain(r.q.to_array())
        .chain(r.q_dot.to_array())
        .chain(r.q_ddot.to_array())
        .chain([
            m1.margins.parallel,
            m1.margins.serial_min,
            l.margins.cos_qs2,
            r.margins.cos_qs2,
        ])
}

/// [`values`] as an array.
pub fn fields<T: Real>(out: &ControlStep<T>) -> [T; FIELD_COUNT] {
    let mut v = [T::zero(); FIELD_COUNT];
    for (slot, x) in v.iter_mut().zip(values(out)) {
        *slot = x;
    }
    v
}
