//! The trajectory planners with arbitrary limits and states, in `f64` and
//! `f32`: trapezoid, double S, the synchronised groups of both, the online
//! profiles (one axis, several, the controlled stop) and the sampler. No
//! call may panic; every plan keeps its limits at every instant sampled,
//! ends exactly at rest on its goal, and a rest-to-rest plan never leaves
//! the segment between its start and its goal.

use parasils::traj::{
    DoubleS, Error, JerkLimits, Limits, Motion, Multi, OnlineMulti, OnlineTrapezoid, Profile,
    State, Synchronization, Trapezoid,
};

use crate::input::{FuzzFloat, Input};

/// The target: the first byte picks the float type, the next the planner.
pub fn trajectory(data: &[u8]) {
    let mut inp = Input::new(data);
    if inp.flag() {
        trajectory_in::<f32>(&mut inp);
    } else {
        trajectory_in::<f64>(&mut inp);
    }
}

/// The instants a plan is checked at: the start, the end, 32 evenly
/// spaced between, and one just inside each end.
fn instants<T: FuzzFloat>(duration: T) -> Vec<T> {
    let d = duration.wide();
    let mut v: Vec<T> = (0..=32).map(|k| T::of(d * f64::from(k) / 32.0)).collect();
    v.push(T::of(d * (1.0 - 4.0 * T::EPS)));
    v.push(T::of(d * 4.0 * T::EPS));
    v
}

/// What one axis must keep: `|v| <= v_max`, `|a| <= a_max`, each up to a
/// relative rounding `rel`, and (rest to rest) the position within
/// `[lo, hi]` up to `tol_p`.
#[derive(Debug, Clone, Copy)]
struct Bounds {
    v_max: f64,
    a_max: f64,
    rel: f64,
    segment: Option<(f64, f64, f64)>,
}

fn check_state<T: FuzzFloat>(what: &str, s: &State<T>, b: &Bounds, t: T) {
    let (p, v, a) = (s.position.wide(), s.velocity.wide(), s.acceleration.wide());
    assert!(
        p.is_finite() && v.is_finite() && a.is_finite(),
        "{what}: a non-finite state {s:?} at t = {t:?} ({})",
        T::NAME
    );
    assert!(
        v.abs() <= b.v_max * (1.0 + b.rel),
        "{what}: |v| = {v:e} above {:e} at t = {t:?} ({})",
        b.v_max,
        T::NAME
    );
    assert!(
        a.abs() <= b.a_max * (1.0 + b.rel),
        "{what}: |a| = {a:e} above {:e} at t = {t:?} ({})",
        b.a_max,
        T::NAME
    );
    if let Some((lo, hi, tol)) = b.segment {
        assert!(
            p >= lo - tol && p <= hi + tol,
            "{what}: position {p:e} outside [{lo:e}, {hi:e}] at t = {t:?} ({})",
            T::NAME
        );
    }
}

fn message(e: &Error) {
    assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
}

/// The rounding allowed on a limit, relative.
fn rel<T: FuzzFloat>() -> f64 {
    16.0 * T::EPS
}

/// Rest-to-rest bounds of a profile from `start` to `goal`.
fn rest_bounds<T: FuzzFloat>(start: T, goal: T, v_max: T, a_max: T) -> Bounds {
    let (s, g) = (start.wide(), goal.wide());
    // The rounding of a position evaluated from its phases, relative to the
    // sizes involved (the property tests' 8 eps, with room for the long
    // times of extreme limits).
    let tol = 32.0 * T::EPS * (s.abs() + g.abs() + (g - s).abs());
    Bounds {
        v_max: v_max.wide(),
        a_max: a_max.wide(),
        rel: rel::<T>(),
        segment: Some((s.min(g), s.max(g), tol)),
    }
}

/// A profile's duration is finite and not negative, it keeps `b` at every
/// instant checked, and it rests exactly on `goal` at its end.
fn check_profile<T: FuzzFloat, P: Profile<T> + core::fmt::Debug>(what: &str, p: &P, b: &Bounds) {
    let d = p.duration();
    assert!(
        d.wide().is_finite() && d.wide() >= 0.0,
        "{what}: duration {d:?} ({})",
        T::NAME
    );
    let what = &format!("{what} {p:?}");
    for t in instants(d) {
        check_state(what, &p.sample(t), b, t);
    }
    assert_eq!(
        p.sample(d),
        State::rest(p.goal()),
        "{what}: not at rest on the goal at the end ({})",
        T::NAME
    );
    assert!(
        p.peak_velocity().wide() <= b.v_max * (1.0 + b.rel)
            && p.peak_acceleration().wide() <= b.a_max * (1.0 + b.rel),
        "{what}: reported peaks above the limits ({})",
        T::NAME
    );
}

/// The sampler over `motion`: an `Ok` sampler's first sample is at `t = 0`
/// and its last at the motion's end, `count` samples in all.
fn check_sampler<T: FuzzFloat, M: Motion<T> + Clone>(what: &str, motion: &M, rate: T)
where
    M::Output: PartialEq + core::fmt::Debug,
{
    match motion.clone().sampler(rate) {
        Ok(mut s) => {
            let n = s.sample_count();
            assert!(n >= 1, "{what}: an empty sampler ({})", T::NAME);
            assert_eq!(s.len(), n, "{what}: the sampler's length ({})", T::NAME);
            let first = s.next().expect("at least one sample");
            assert_eq!(first.time.wide(), 0.0, "{what}: the first sample's time");
            if let Some(last) = s.next_back() {
                assert_eq!(
                    last.state,
                    motion.sample(motion.duration()),
                    "{what}: the last sample is not the end ({})",
                    T::NAME
                );
            }
        }
        Err(e) => message(&e),
    }
}

fn limits_in<T: FuzzFloat>(inp: &mut Input) -> Limits<T> {
    Limits::new(inp.real(), inp.real())
}

fn sync_in(inp: &mut Input) -> Synchronization {
    match inp.choose(3) {
        0 => Synchronization::Phase,
        1 => Synchronization::Time,
        _ => Synchronization::None,
    }
}

fn state_in<T: FuzzFloat>(inp: &mut Input) -> State<T> {
    State {
        position: inp.real(),
        velocity: inp.real(),
        acceleration: inp.real(),
    }
}

/// Online bounds: `v_max`, or the start's own speed if faster (the plan
/// brakes from it), `a_max`; no segment (an online plan may overshoot).
fn online_bounds<T: FuzzFloat>(start: &State<T>, l: &Limits<T>, stop: bool) -> Bounds {
    let v0 = start.velocity.wide().abs();
    Bounds {
        v_max: if stop { v0 } else { l.v_max.wide().max(v0) },
        a_max: l.a_max.wide(),
        rel: rel::<T>(),
        segment: None,
    }
}

fn check_online<T: FuzzFloat>(what: &str, p: &OnlineTrapezoid<T>, b: &Bounds) {
    let d = p.duration();
    assert!(
        d.wide().is_finite() && d.wide() >= 0.0,
        "{what}: duration {d:?} ({})",
        T::NAME
    );
    for t in instants(d) {
        check_state(what, &p.sample(t), b, t);
    }
    assert_eq!(
        p.sample(d),
        State::rest(p.target()),
        "{what}: not at rest on the target at the end ({}): {p:?}",
        T::NAME
    );
}

fn trajectory_in<T: FuzzFloat>(inp: &mut Input) {
    match inp.choose(8) {
        0 => {
            let (start, goal, l) = (inp.real::<T>(), inp.real::<T>(), limits_in::<T>(inp));
            let p = if inp.flag() {
                Trapezoid::with_duration(start, goal, l, inp.real())
            } else {
                Trapezoid::new(start, goal, l)
            };
            match p {
                Ok(p) => {
                    check_profile("trapezoid", &p, &rest_bounds(start, goal, l.v_max, l.a_max));
                    check_sampler("trapezoid", &p, inp.real());
                }
                Err(e) => message(&e),
            }
        }
        1 => {
            let (start, goal) = (inp.real::<T>(), inp.real::<T>());
            let l = JerkLimits::new(inp.real(), inp.real(), inp.real());
            let p = if inp.flag() {
                DoubleS::with_duration(start, goal, l, inp.real())
            } else {
                DoubleS::new(start, goal, l)
            };
            match p {
                Ok(p) => {
                    check_profile("double S", &p, &rest_bounds(start, goal, l.v_max, l.a_max));
                    let j = l.j_max.wide();
                    for t in instants(p.duration()) {
                        let jt = p.jerk(t).wide();
                        assert!(
                            jt.abs() <= j * (1.0 + rel::<T>()),
                            "double S: |jerk| {jt:e} above {j:e} ({})",
                            T::NAME
                        );
                    }
                    check_sampler("double S", &p, inp.real());
                }
                Err(e) => message(&e),
            }
        }
        2 => {
            let start: [T; 2] = inp.reals();
            let goal: [T; 2] = inp.reals();
            let limits = [limits_in::<T>(inp), limits_in::<T>(inp)];
            match Multi::new(start, goal, limits, sync_in(inp)) {
                Ok(m) => {
                    for (i, (ax, l)) in m.axes().iter().zip(&limits).enumerate() {
                        let b = rest_bounds(start[i], goal[i], l.v_max, l.a_max);
                        check_profile("synchronised trapezoids", ax, &b);
                    }
                    check_sampler("synchronised trapezoids", &m, inp.real());
                }
                Err(e) => message(&e),
            }
        }
        3 => {
            let start: [T; 2] = inp.reals();
            let goal: [T; 2] = inp.reals();
            let limits: [JerkLimits<T>; 2] =
                core::array::from_fn(|_| JerkLimits::new(inp.real(), inp.real(), inp.real()));
            match Multi::double_s(start, goal, limits, sync_in(inp)) {
                Ok(m) => {
                    for (i, (ax, l)) in m.axes().iter().zip(&limits).enumerate() {
                        let b = rest_bounds(start[i], goal[i], l.v_max, l.a_max);
                        check_profile("synchronised double S", ax, &b);
                    }
                    check_sampler("synchronised double S", &m, inp.real());
                }
                Err(e) => message(&e),
            }
        }
        4 => {
            let (start, target, l) = (state_in::<T>(inp), inp.real::<T>(), limits_in::<T>(inp));
            let p = if inp.flag() {
                OnlineTrapezoid::with_duration(start, target, l, inp.real())
            } else {
                OnlineTrapezoid::new(start, target, l)
            };
            match p {
                Ok(p) => {
                    check_online("online", &p, &online_bounds(&start, &l, false));
                    check_sampler("online", &p, inp.real());
                }
                Err(e) => message(&e),
            }
        }
        5 => {
            let (start, l) = (state_in::<T>(inp), limits_in::<T>(inp));
            match OnlineTrapezoid::stop(start, l) {
                Ok(p) => check_online("stop", &p, &online_bounds(&start, &l, true)),
                Err(e) => message(&e),
            }
        }
        6 => {
            let start = [state_in::<T>(inp), state_in::<T>(inp)];
            let target: [T; 2] = inp.reals();
            let limits = [limits_in::<T>(inp), limits_in::<T>(inp)];
            match OnlineMulti::new(start, target, limits, sync_in(inp)) {
                Ok(m) => {
                    for (i, (ax, l)) in m.axes().iter().zip(&limits).enumerate() {
                        check_online("online group", ax, &online_bounds(&start[i], l, false));
                    }
                    check_sampler("online group", &m, inp.real());
                }
                Err(e) => message(&e),
            }
        }
        _ => {
            let start = [state_in::<T>(inp), state_in::<T>(inp)];
            let limits = [limits_in::<T>(inp), limits_in::<T>(inp)];
            match OnlineMulti::stop(start, limits) {
                Ok(m) => {
                    for (i, (ax, l)) in m.axes().iter().zip(&limits).enumerate() {
                        check_online("group stop", ax, &online_bounds(&start[i], l, true));
                    }
                }
                Err(e) => message(&e),
            }
        }
    }
}
