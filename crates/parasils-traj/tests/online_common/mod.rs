//! Shared problems and checks of the online profiles' property tests
//! (`online_axis`, `online_multi`, `stop`): random one-axis problems, the
//! rounding and time slack they allow, the checks every profile passes, and
//! an independent reference for the minimum time.
#![allow(dead_code)]
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact start states are what these checks test"
)]

use crate::common::{c, log_uniform, near_zero};
use parasils_traj::{Error, Limits, OnlineTrapezoid, Real, State, Trapezoid};
use proptest::prelude::*;

/// Cases per property.
pub const CASES: u32 = 100_000;

pub fn fail(e: Error) -> TestCaseError {
    TestCaseError::fail(format!("{e}"))
}

pub fn moving<T: Real>(position: T, velocity: T) -> State<T> {
    State {
        position,
        velocity,
        acceleration: T::zero(),
    }
}

/// One axis's problem, drawn in f64 and converted to the type under test.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    pub p0: f64,
    pub v0: f64,
    pub target: f64,
    pub v_max: f64,
    pub a_max: f64,
}

impl Case {
    pub fn start<T: Real>(&self) -> State<T> {
        moving(c(self.p0), c(self.v0))
    }
    pub fn target<T: Real>(&self) -> T {
        c(self.target)
    }
    pub fn limits<T: Real>(&self) -> Limits<T> {
        Limits::new(c(self.v_max), c(self.a_max))
    }
}

/// Random problems: positions in `-p..p`, distances `10^(lo..hi)`, limits
/// `10^(vl)`, `10^(al)`, velocities up to 1.5 `v_max` (and exactly 0 or
/// `+-v_max`), targets anywhere, on the start, or at or near the stopping point.
pub fn case(
    p: f64,
    lo: f64,
    hi: f64,
    vl: (f64, f64),
    al: (f64, f64),
) -> impl Strategy<Value = Case> + Clone {
    let factor = prop_oneof![
        1 => Just(0.0),
        1 => Just(1.0),
        1 => Just(-1.0),
        6 => -1.5..1.5_f64,
    ];
    let signed = (log_uniform(lo, hi), any::<bool>()).prop_map(|(d, n)| if n { -d } else { d });
    // 0: from p0; 1: from the stopping point, offset by `d`; 2: the stopping point times (1 + small).
    let target = prop_oneof![
        4 => (Just(0_u8), signed.clone()),
        1 => (Just(0_u8), Just(0.0)),
        2 => (Just(1_u8), signed),
        2 => (Just(2_u8), near_zero()),
    ];
    (
        -p..p,
        factor,
        target,
        log_uniform(vl.0, vl.1),
        log_uniform(al.0, al.1),
    )
        .prop_map(|(p0, f, (kind, off), v_max, a_max)| {
            let v0 = f * v_max;
            let stop = 0.5 * v0 * v0.abs() / a_max;
            let target = match kind {
                0 => p0 + off,
                1 => p0 + stop + off,
                _ => p0 + stop * (1.0 + off),
            };
            Case {
                p0,
                v0,
                target,
                v_max,
                a_max,
            }
        })
}

pub fn case_f64() -> impl Strategy<Value = Case> + Clone {
    case(1e2, -3.0, 3.0, (-2.0, 2.0), (-2.0, 3.0))
}

pub fn case_f32() -> impl Strategy<Value = Case> + Clone {
    case(10.0, -2.0, 2.0, (-1.0, 1.0), (-1.0, 2.0))
}

/// The rounding of positions of one axis: 16 eps of the largest position involved.
pub fn rounding<T: Real>(p0: T, v0: T, target: T, a_max: T) -> T {
    let stop = v0 * v0 / a_max;
    c::<T>(16.0) * T::EPSILON * (p0.abs() + target.abs() + stop)
}

/// How far a duration may move when the positions move by `delta`: the time
/// to cover `delta` at the slowest velocity the profile can be at when it
/// matters, `min(v_max, sqrt(a_max |gap|))`, `gap` the distance from the
/// stopping point to the target (at least `delta`).
pub fn time_slack<T: Real>(delta: T, gap: T, lim: Limits<T>) -> T {
    if delta == T::zero() {
        return T::zero();
    }
    let v = lim.v_max.min((lim.a_max * gap.abs().max(delta)).sqrt());
    c::<T>(4.0) * delta / v
}

/// Times in `(0, T)`: a grid of `m` points, the switches and their neighbours.
pub fn times<T: Real>(t_end: T, switches: &[T], m: usize) -> Vec<T> {
    let mut v: Vec<T> = (1..m)
        .map(|k| t_end * T::from_index(k) / T::from_index(m))
        .collect();
    let nudge = t_end * T::EPSILON * c(4.0);
    for &s in switches {
        for t in [s - nudge, s, s + nudge] {
            if t > T::zero() && t < t_end {
                v.push(t);
            }
        }
    }
    v.sort_by(|x, y| x.partial_cmp(y).unwrap_or(core::cmp::Ordering::Equal));
    v
}

/// The conventions at the ends, the limits, continuity at the switches and at
/// the end, and (when `monotone`) a position that never goes back.
pub fn check_profile<T: Real>(
    p: &OnlineTrapezoid<T>,
    lim: Limits<T>,
    monotone: bool,
) -> Result<(), TestCaseError> {
    let (p0, v0, target, t_end) = (p.start(), p.start_velocity(), p.target(), p.duration());
    let start = moving(p0, v0);
    prop_assert_eq!(p.sample(T::zero()), start);
    prop_assert_eq!(p.sample(-T::one()), start);
    prop_assert_eq!(p.sample(T::lit(f64::NAN)), start);
    prop_assert_eq!(p.sample(t_end), State::rest(target));
    prop_assert_eq!(p.sample(t_end + t_end + T::one()), State::rest(target));
    prop_assert_eq!(p.sample(T::INFINITY), State::rest(target));
    prop_assert!(t_end.is_finite() && t_end >= T::zero());

    let rel = T::one() + c::<T>(16.0) * T::EPSILON;
    // The rounding of the positions met: 16 eps of the largest.
    let tol_p =
        rounding(p0, v0, target, lim.a_max) + c::<T>(16.0) * T::EPSILON * p.peak_velocity() * t_end;
    let (lo, hi) = (p0.min(target), p0.max(target));
    let dir = (target - p0).signum();
    let braking = v0.abs() > lim.v_max;
    let mut prev = moving(p0, v0);
    let mut prev_t = T::zero();
    for t in times(t_end, &p.switches(), 24) {
        let s = p.sample(t);
        prop_assert!(
            s.position.is_finite() && s.velocity.is_finite() && s.acceleration.is_finite()
        );
        prop_assert!(
            s.acceleration.abs() <= lim.a_max * rel,
            "a {:?} > {:?} at {:?}",
            s.acceleration,
            lim.a_max,
            t
        );
        let v_bound = if braking && t < p.t_first() {
            v0.abs()
        } else {
            lim.v_max
        };
        prop_assert!(
            s.velocity.abs() <= v_bound * rel,
            "v {:?} > {:?} at {:?}",
            s.velocity,
            v_bound,
            t
        );
        // Continuity: the position moves by what the velocities explain.
        let dt = t - prev_t;
        let expect = prev.position + T::lit(0.5) * (prev.velocity + s.velocity) * dt;
        let tol_step = tol_p + lim.a_max * dt * dt;
        prop_assert!(
            (s.position - expect).abs() <= tol_step,
            "position jumps from {:?} to {:?} over {:?} s at {:?}",
            prev.position,
            s.position,
            dt,
            t
        );
        // Rounding of `v0 + a t`.
        let tol_v = c::<T>(16.0) * T::EPSILON * (v0.abs() + lim.v_max + lim.a_max * t);
        prop_assert!(
            (s.velocity - prev.velocity).abs() <= lim.a_max * dt * rel + tol_v,
            "velocity jumps from {:?} to {:?} at {:?}",
            prev.velocity,
            s.velocity,
            t
        );
        if monotone {
            prop_assert!(
                s.position >= lo - tol_p && s.position <= hi + tol_p,
                "overshoot: {:?} at {:?}",
                s.position,
                t
            );
            prop_assert!(
                (s.position - prev.position) * dir >= -tol_p,
                "goes back: {:?} after {:?} at {:?}",
                s.position,
                prev.position,
                t
            );
        }
        prev = s;
        prev_t = t;
    }
    // The last phase ends on the target at rest.
    let dt = t_end - prev_t;
    prop_assert!(
        (target - prev.position - T::lit(0.5) * prev.velocity * dt).abs()
            <= tol_p + lim.a_max * dt * dt
    );
    prop_assert!(
        prev.velocity.abs() <= lim.a_max * dt * rel + c::<T>(16.0) * T::EPSILON * lim.v_max
    );
    Ok(())
}

/// True when `v0` points towards the target (or is zero) and the target is
/// beyond the stopping point: no overshoot is needed.
pub fn needs_no_overshoot<T: Real>(p0: T, v0: T, target: T, lim: Limits<T>) -> bool {
    let d = target - p0;
    let stop = T::lit(0.5) * v0 * v0 / lim.a_max;
    v0 * d >= T::zero() && d.abs() >= stop
}

/// The minimum time, written independently of the implementation (from the
/// rest-to-rest trapezoid): the axis either passes through rest at its
/// stopping point (moving away, or the target before the stopping point), or
/// is the tail of a rest-to-rest profile from a virtual start, or brakes to
/// `v_max` and cruises. Also returns the upper bound of the requirements,
/// braking to rest then rest-to-rest.
pub fn reference<T: Real>(
    p0: T,
    v0: T,
    target: T,
    lim: Limits<T>,
) -> Result<(T, T), TestCaseError> {
    let half = T::lit(0.5);
    let (vm, am) = (lim.v_max, lim.a_max);
    let t_brake = v0.abs() / am;
    let stop = p0 + half * v0 * v0.abs() / am;
    let bound = t_brake + Trapezoid::new(stop, target, lim).map_err(fail)?.duration();
    let d = target - p0;
    let exact = if needs_no_overshoot(p0, v0, target, lim) {
        if v0.abs() <= vm {
            let virtual_start = p0 - half * v0 * v0.abs() / am;
            Trapezoid::new(virtual_start, target, lim)
                .map_err(fail)?
                .duration()
                - t_brake
        } else {
            t_brake + (d.abs() - half * v0 * v0 / am) / vm
        }
    } else {
        bound
    };
    Ok((exact, bound))
}

/// Every single-axis check; returns the profile.
/// Any f64 bit pattern (NaN, infinities, subnormals included), or a
/// moderate value so that valid problems are drawn too.
pub fn anything() -> impl Strategy<Value = f64> {
    prop_oneof![any::<f64>(), -1e3..1e3_f64]
}

/// Limits shared by every axis, or drawn for each.
pub fn group<const N: usize>(
    one: impl Strategy<Value = Case> + Clone,
) -> impl Strategy<Value = [Case; N]> {
    (proptest::array::uniform::<_, N>(one), any::<bool>()).prop_map(|(mut ks, same)| {
        if same {
            let (v, a) = (ks[0].v_max, ks[0].a_max);
            for k in &mut ks {
                k.v_max = v;
                k.a_max = a;
            }
        }
        ks
    })
}
