//! What the firmware (`f32`, on the MCU) and `build.rs` (`f64`, on the host,
//! for the references) share word for word: the command stream, the
//! controller it drives, which cycles are compared, and the values of a
//! cycle that are compared.
//!
//! The stream, at [`RATE_HZ`] (1 kHz) from `P0` ([`Pose::paper_start`]), each
//! angle within 10 deg/s and 5 deg/s^2:
//!
//! | cycle | t | command |
//! |---|---|---|
//! | 0 | 0 s | the paper's goal: `psi` +15, `theta` +25 deg from `P0` |
//! | 1200 | 1.2 s | a new goal while turning: `psi` -10, `theta` +15 deg (`psi` turns back) |
//! | 3000 | 3.0 s | the controlled stop, while moving towards it |
//! | 3500 | 3.5 s | a third goal while still braking: `psi` +5, `theta` +10 deg |
//! | 5000 | 5.0 s | look at the tips' midpoint, while turning: the goal from [`OnlineController::command_look_at`] (the camera at the endoscope's tip, depth 0 here) |
//!
//! and the loop runs until the platform rests on the look-at goal. See
//! `docs/model.md`, *Trajectories* and *Check values*.
//!
//! Every cycle also computes the twelve actuators' feedforward forces
//! ([`forces`]) holding both tips' loads ([`TIP_LOADS_N`]) and moving the
//! assumed platform body ([`loads`]), compared with the references like the
//! rest.
//!
//! The controller watches the clearance of the assumed bodies (shafts of 5
//! mm, the endoscope of 10 mm at depth 0): every cycle computes the three
//! gaps between them and checks them ahead, and they are compared with the
//! references like the rest. Its thresholds (-1000 mm) are ones no gap
//! reaches: with the paper's tips the shafts overlap from the start
//! (`docs/model.md`, *Clearance*), so this run measures the clearance and
//! its cost, it does not stop on it.

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{BodyGeometry, ControlStep, Controller, Loads, Payload, Pose, TipTargets};
use parasils::supervisor::ClearanceThresholds;
use parasils::traj::{Limits, Synchronization};
use parasils::{ClearanceWatch, Error, OnlineController, Real, Setpoint, Supervisor};

/// The control rate, Hz.
pub const RATE_HZ: f64 = parasils::paper::RATE_HZ;

/// The velocity and acceleration limits of `psi` and `theta`, deg/s and
/// deg/s^2 (the paper's).
pub const LIMITS_DEG: [f64; 2] = [
    parasils::paper::OMEGA_MAX_DEG_S,
    parasils::paper::EPS_MAX_DEG_S2,
];

/// What a command of the stream asks, as written in [`COMMANDS`].
#[derive(Clone, Copy)]
pub enum Ask {
    /// A goal `[psi, theta]`, deg from `P0`.
    GoalDeg([f64; 2]),
    /// The controlled stop.
    Stop,
    /// Aim the camera at the midpoint of the two tips.
    LookAtTips,
}

/// A command of the stream: at `cycle`, what it asks; `label` for the
/// report.
#[derive(Clone, Copy)]
pub struct Command {
    /// The cycle it is given at (`t = cycle / RATE_HZ`).
    pub cycle: usize,
    /// What it asks.
    pub ask: Ask,
    /// What it is, for the report.
    pub label: &'static str,
}

/// A command as the controller takes it.
#[derive(Clone, Copy)]
pub enum Order<T: Real> {
    /// A goal `[psi, theta]`, rad (absolute).
    Goal([T; 2]),
    /// The controlled stop.
    Stop,
    /// A look-at target, mm, fixed frame.
    LookAt(Vector3<T>),
}

/// The stream (see the [module docs](self)).
pub const COMMANDS: [Command; 5] = [
    Command {
        cycle: 0,
        ask: Ask::GoalDeg([15.0, 25.0]),
        label: "the paper's goal, psi +15 theta +25 deg",
    },
    Command {
        cycle: 1200,
        ask: Ask::GoalDeg([-10.0, 15.0]),
        label: "new goal while turning, psi -10 theta +15 deg",
    },
    Command {
        cycle: 3000,
        ask: Ask::Stop,
        label: "controlled stop",
    },
    Command {
        cycle: 3500,
        ask: Ask::GoalDeg([5.0, 10.0]),
        label: "third goal while braking, psi +5 theta +10 deg",
    },
    Command {
        cycle: 5000,
        ask: Ask::LookAtTips,
        label: "look at the tips' midpoint while turning",
    },
];

/// An upper bound of the run's cycles (the run has 11178): the loop
/// never runs longer, whatever happens.
pub const MAX_CYCLES: usize = 15_000;

/// Every how many cycles the firmware compares its `f32` results with the
/// host's `f64` references; every command's cycle and the last cycle are
/// compared too.
pub const REFERENCE_EVERY: usize = 250;

/// Whether cycle `k` of a run of `cycles` is compared with its reference.
pub fn compared(k: usize, cycles: usize) -> bool {
    k.is_multiple_of(REFERENCE_EVERY) || k + 1 == cycles || COMMANDS.iter().any(|c| c.cycle == k)
}

/// The time of cycle `k`, s.
pub fn time<T: Real>(k: usize) -> T {
    T::from_index(k) / T::lit(RATE_HZ)
}

/// The controller at rest at `P0`, holding the paper's tips, with the limits
/// [`LIMITS_DEG`] and the default supervisor, watching the clearance (see
/// the module docs).
pub fn online<T: Real>() -> Result<OnlineController<T>, Error> {
    let [v, a] = LIMITS_DEG.map(|x| T::lit(x.to_radians()));
    OnlineController::new(
        Controller::paper(),
        TipTargets::paper(),
        Pose::paper_start(),
        [Limits::new(v, a); 2],
        Supervisor::default(),
    )?
    .with_clearance(ClearanceWatch {
        bodies: BodyGeometry::assumed(),
        endoscope_depth: T::zero(),
        thresholds: ClearanceThresholds {
            warn: T::lit(-1000.0),
            stop: T::lit(-1000.0),
        },
    })
}

/// The commands as the controller takes them: `(cycle, order)`, a goal in
/// rad (absolute), the stop, or a look-at target in mm (the midpoint of the
/// paper's tips, computed in `T`). Computed once, outside the loop.
pub fn orders<T: Real>() -> [(usize, Order<T>); COMMANDS.len()] {
    let p0 = Pose::<f64>::paper_start();
    let lit = |x: f64| T::lit(x);
    let tips = TipTargets::<T>::paper();
    let midpoint = (tips.left + tips.right) / T::lit(2.0);
    COMMANDS.map(|c| {
        (
            c.cycle,
            match c.ask {
                Ask::GoalDeg([psi, theta]) => Order::Goal([
                    lit(p0.psi + psi.to_radians()),
                    lit(p0.theta + theta.to_radians()),
                ]),
                Ask::Stop => Order::Stop,
                Ask::LookAtTips => Order::LookAt(midpoint),
            },
        )
    })
}

/// Gives `order` to the controller at `t`: the synchronisation of a goal
/// or a look-at, `None` for the stop.
#[inline(always)]
pub fn give<T: Real>(
    online: &mut OnlineController<T>,
    t: T,
    order: Order<T>,
) -> Result<Option<Synchronization>, Error> {
    match order {
        Order::Goal(g) => online.command(t, g).map(Some),
        Order::Stop => online.stop(t).map(|()| None),
        Order::LookAt(target) => online.command_look_at(t, target).map(Some),
    }
}

/// The force each tip exerts on the tissue, N, fixed frame, `[left,
/// right]`: what the feedforward forces hold every cycle, with the
/// platform's body ([`loads`]).
pub const TIP_LOADS_N: [[f64; 3]; 2] = [[2.0, -3.0, -5.0], [-1.5, 2.0, -4.0]];

/// What every cycle's feedforward forces hold: both tips pressing with
/// [`TIP_LOADS_N`], and the assumed platform body
/// ([`Payload::assumed`]: 6 kg, its weight and its Newton-Euler inertia in
/// the cycle's motion).
pub fn loads<T: Real>() -> Loads<T> {
    let tip = |f: [f64; 3]| Vector3::new(T::lit(f[0]), T::lit(f[1]), T::lit(f[2]));
    Loads {
        payload: Payload::assumed(),
        ..Loads::tips(tip(TIP_LOADS_N[0]), tip(TIP_LOADS_N[1]))
    }
}

/// The twelve actuators' feedforward forces of the cycle `step` holding
/// `loads` (`Controller::forces`): `q1..q6` N, each module's `qs1`, `qs2`
/// N mm and `qs3` N.
#[inline(always)]
pub fn forces<T: Real>(
    controller: &Controller<T>,
    step: &ControlStep<T>,
    loads: &Loads<T>,
) -> Result<[T; 12], Error> {
    controller
        .forces(step, loads)
        .map(|f| f.to_array())
        .map_err(Error::Kinematics)
}

/// How many values of a cycle are compared, see [`fields`].
pub const FIELD_COUNT: usize = 61;

/// The names of the values of [`fields`], in order (units: mm, rad, s).
pub const FIELD_NAMES: [&str; FIELD_COUNT] = [
    "psi",
    "theta",
    "psi_dot",
    "theta_dot",
    "psi_ddot",
    "theta_ddot", //
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
    "right.cos_qs2", //
    "clearance.left_right",
    "clearance.left_endoscope",
    "clearance.right_endoscope", //
    "force.q1",
    "force.q2",
    "force.q3",
    "force.q4",
    "force.q5",
    "force.q6", //
    "force.left.qs1",
    "force.left.qs2",
    "force.left.qs3",
    "force.right.qs1",
    "force.right.qs2",
    "force.right.qs3",
];

/// How a field is compared (see `tolerance` in `main.rs`).
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// An angle, rad: absolute tolerance.
    Angle,
    /// A length, mm: absolute tolerance.
    Length,
    /// A rate or an acceleration: tolerance relative to the field's peak
    /// magnitude over the whole run.
    Rate,
    /// A dimensionless margin: absolute tolerance.
    Margin,
    /// A force or a torque: tolerance relative to the field's peak
    /// magnitude over the whole run.
    Force,
}

/// The kind of each field of [`fields`].
pub const FIELD_KINDS: [Kind; FIELD_COUNT] = {
    use Kind::{Angle as A, Force as F, Length as L, Margin as M, Rate as R};
    [
        A, A, R, R, R, R, //
        L, L, L, L, L, L, R, R, R, R, R, R, R, R, R, R, R, R, //
        A, A, L, R, R, R, R, R, R, //
        A, A, L, R, R, R, R, R, R, //
        M, M, M, M, //
        L, L, L, //
        F, F, F, F, F, F, F, F, F, F, F, F,
    ]
};

/// The values of one cycle that the firmware compares with the host's, in
/// the order of [`FIELD_NAMES`], the cycle's feedforward `forces` last
/// (`build.rs` checks that there are exactly [`FIELD_COUNT`]).
pub fn values<T: Real>(s: &Setpoint<T>, forces: &[T; 12]) -> impl Iterator<Item = T> {
    let p = &s.state;
    [
        p.pose.psi,
        p.pose.theta,
        p.velocity.psi,
        p.velocity.theta,
        p.acceleration.psi,
        p.acceleration.theta,
    ]
    .into_iter()
    .chain(step_values(&s.step))
    .chain(gaps(s))
    .chain(*forces)
}

/// The three clearance gaps of a cycle, mm (NaN, which matches nothing,
/// if the controller watched none).
fn gaps<T: Real>(s: &Setpoint<T>) -> [T; 3] {
    s.clearance.map_or([T::lit(f64::NAN); 3], |c| {
        [
            c.left_right.gap,
            c.left_endoscope.gap,
            c.right_endoscope.gap,
        ]
    })
}

fn step_values<T: Real>(out: &ControlStep<T>) -> impl Iterator<Item = T> {
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
pub fn fields<T: Real>(s: &Setpoint<T>, forces: &[T; 12]) -> [T; FIELD_COUNT] {
    let mut v = [T::zero(); FIELD_COUNT];
    for (slot, x) in v.iter_mut().zip(values(s, forces)) {
        *slot = x;
    }
    v
}
