//! The kinematics with arbitrary `f64` and `f32` bit patterns: the
//! instrument modules' IK and FK, module 1's IK and FK, and the controller's
//! step. No call may panic; every `Ok` result is finite; every `Ok` IK goes
//! back through FK to its input within the rounding of the numbers involved.
//!
//! The first byte of an input picks the float type, so that one corpus file
//! exercises one precision.

use nalgebra::Vector3;
use parasils::kin::{
    Actuators, AssemblyMode, Controller, Error, FkOptions, Instrument, InstrumentGeometry,
    InstrumentSolution, Joints, MarginTracker, ParallelGeometry, ParallelRobot, ParallelSolution,
    PlatformState, Pose, PoseRate, Side, TipMotion, TipTargets,
};

use crate::input::{FuzzFloat, Input};

/// The instrument modules' target: geometry, IK in both modes (limits
/// checked or not), FK, the solve with rates.
pub fn instrument(data: &[u8]) {
    let mut inp = Input::new(data);
    if inp.flag() {
        instrument_in::<f32>(&mut inp);
    } else {
        instrument_in::<f64>(&mut inp);
    }
}

/// Module 1's target: IK, FK from a guess near or far, the solve with rates
/// and margins, over the assumed geometry or one with fuzzed dimensions.
pub fn module1(data: &[u8]) {
    let mut inp = Input::new(data);
    if inp.flag() {
        module1_in::<f32>(&mut inp);
    } else {
        module1_in::<f64>(&mut inp);
    }
}

/// The controller's target: a few steps with arbitrary platform states and
/// tips.
pub fn controller(data: &[u8]) {
    let mut inp = Input::new(data);
    if inp.flag() {
        controller_in::<f32>(&mut inp);
    } else {
        controller_in::<f64>(&mut inp);
    }
}

/// The error's message is written without panicking and is not empty.
fn message(e: &Error) {
    let text = e.to_string();
    assert!(!text.is_empty(), "an empty message for {e:?}");
}

fn finite<T: FuzzFloat>(what: &str, values: &[T]) {
    for v in values {
        assert!(
            v.wide().is_finite(),
            "{what}: {} in an Ok result ({})",
            v.wide(),
            T::NAME
        );
    }
}

fn norm<T: FuzzFloat>(v: &Vector3<T>) -> f64 {
    let [x, y, z] = [v.x.wide(), v.y.wide(), v.z.wide()];
    (x * x + y * y + z * z).sqrt()
}

fn pose_in<T: FuzzFloat>(inp: &mut Input) -> Pose<T> {
    let p: [T; 6] = inp.reals();
    if inp.flag() {
        // Around the paper's start pose, where the robot works.
        let start = Pose::<T>::paper_start().to_array();
        Pose::from_array(core::array::from_fn(|i| start[i] + p[i] * T::of(1e-3)))
    } else {
        Pose::from_array(p)
    }
}

fn rate_in<T: FuzzFloat>(inp: &mut Input) -> PoseRate<T> {
    let [x, y, z, psi, theta, phi] = inp.reals::<T, 6>();
    PoseRate {
        x,
        y,
        z,
        psi,
        theta,
        phi,
    }
}

fn state_in<T: FuzzFloat>(inp: &mut Input) -> PlatformState<T> {
    let pose = pose_in(inp);
    if inp.flag() {
        PlatformState::at_rest(pose)
    } else {
        PlatformState {
            pose,
            velocity: rate_in(inp),
            acceleration: rate_in(inp),
        }
    }
}

fn vector_in<T: FuzzFloat>(inp: &mut Input) -> Vector3<T> {
    let [x, y, z] = inp.reals();
    Vector3::new(x, y, z)
}

fn joints_finite<T: FuzzFloat>(what: &str, q: &Joints<T>) {
    finite(what, &q.to_array());
}

fn instrument_solution_finite<T: FuzzFloat>(s: &InstrumentSolution<T>) {
    joints_finite("q", &s.q);
    joints_finite("q_dot", &s.q_dot);
    joints_finite("q_ddot", &s.q_ddot);
    let m = &s.margins;
    finite("margins", &[m.cos_qs2, m.qs3]);
    joints_finite("margins.limits", &m.limits);
}

fn parallel_solution_finite<T: FuzzFloat>(s: &ParallelSolution<T>) {
    finite("q", &s.q.0);
    finite("q_dot", &s.q_dot.0);
    finite("q_ddot", &s.q_ddot.0);
    let m = &s.margins;
    finite("serial margins", &m.serial);
    finite("margins", &[m.serial_min, m.parallel]);
    finite("stroke margins", &m.stroke);
}

/// The paper's module, or one whose every parameter the fuzzer chose.
fn instrument_geometry_in<T: FuzzFloat>(inp: &mut Input, side: Side) -> InstrumentGeometry<T> {
    let mut g = InstrumentGeometry::<T>::paper(side);
    if inp.flag() {
        g.alpha = inp.real();
        g.beta = inp.real();
        g.radius = inp.real();
        g.rcm = vector_in(inp);
        g.thresholds.reach = inp.real();
        g.thresholds.cos_qs2 = inp.real();
        g.thresholds.qs3 = inp.real();
    }
    g
}

/// How far `FK(IK(x))` may land from `x`, mm: the rounding of the numbers
/// the round trip goes through, and where the reach test's tolerance lets a
/// tip a little outside the reachable cone in, the distance that clamping
/// its direction onto the cone moves it.
fn tip_tolerance<T: FuzzFloat>(
    m: &Instrument<T>,
    pose: &Pose<T>,
    tip: &Vector3<T>,
    q: &Joints<T>,
) -> f64 {
    let g = m.geometry();
    let eps = T::EPS;
    // qs1 comes from an atan2 of numbers of the size of cos(qs2): its
    // rounding, and so the tip's, grows as 1 / |cos qs2| towards the edge of
    // the cone (the singularity the thresholds keep away).
    let qs3 = q.qs3.wide().abs();
    let cos_qs2 = q.qs2.wide().cos().abs().max(f64::MIN_POSITIVE);
    let scale = norm(tip) + norm(&pose.position()) + norm(&g.rcm) + qs3 + qs3 / cos_qs2;
    let reach = g.thresholds.reach.wide();
    let clamp = if cos_qs2 <= 4.0 * reach.sqrt() {
        2.0 * (2.0 * reach).sqrt() * qs3
    } else {
        0.0
    };
    64.0 * eps * scale + clamp
}

/// Checks `FK(IK(tip)) = tip` for an `Ok` IK.
fn tip_round_trip<T: FuzzFloat>(
    m: &Instrument<T>,
    pose: &Pose<T>,
    tip: &Vector3<T>,
    q: &Joints<T>,
) {
    joints_finite("IK", q);
    let back = match m.fk(pose, q) {
        Ok(back) => back,
        Err(e) => panic!("FK of the IK's own joints {q:?} failed ({}): {e}", T::NAME),
    };
    finite("FK(IK)", back.as_slice());
    let err = norm(&(back - tip));
    let tol = tip_tolerance(m, pose, tip, q);
    assert!(
        err <= tol,
        "FK(IK(tip)) is {err:e} mm from the tip, above {tol:e} ({}): tip {tip:?}, q {q:?}, pose {pose:?}",
        T::NAME
    );
}

fn instrument_in<T: FuzzFloat>(inp: &mut Input) {
    let side = if inp.flag() { Side::Right } else { Side::Left };
    let geometry = instrument_geometry_in::<T>(inp, side);
    let m = match Instrument::new(geometry) {
        Ok(m) => m,
        Err(e) => return message(&e),
    };
    let pose = pose_in::<T>(inp);
    let mode = if inp.flag() {
        AssemblyMode::B
    } else {
        AssemblyMode::A
    };
    match inp.choose(4) {
        // IK of an arbitrary tip, both modes, limits not checked.
        0 => {
            let tip = vector_in::<T>(inp);
            match m.ik_solutions(&pose, &tip) {
                Ok(both) => {
                    for q in &both {
                        tip_round_trip(&m, &pose, &tip, q);
                    }
                }
                Err(e) => message(&e),
            }
        }
        // FK of arbitrary joints, then IK of that tip in the joints' mode
        // with limits checked (or continuing from the joints).
        1 => {
            let q = Joints::new(inp.real(), inp.real(), inp.real());
            let tip = match m.fk(&pose, &q) {
                Ok(tip) => tip,
                Err(e) => return message(&e),
            };
            if !tip.iter().all(|v| v.wide().is_finite()) {
                // Finite joints whose tip overflows: FK must refuse them.
                panic!(
                    "FK returned {tip:?} for finite joints {q:?} at {pose:?} ({})",
                    T::NAME
                );
            }
            let ik = if inp.flag() {
                m.ik_continuing(&pose, &tip, &q)
            } else {
                m.ik(&pose, &tip, AssemblyMode::of(&q))
            };
            match ik {
                Ok(back) => tip_round_trip(&m, &pose, &tip, &back),
                Err(e) => message(&e),
            }
        }
        // The solve with rates and accelerations.
        2 => {
            let state = state_in::<T>(inp);
            let tip = TipMotion {
                position: vector_in(inp),
                velocity: vector_in(inp),
                acceleration: vector_in(inp),
            };
            let frame = match state.frame() {
                Ok(frame) => frame,
                Err(e) => return message(&e),
            };
            match m.solve(&frame, &tip, mode) {
                Ok(s) => {
                    instrument_solution_finite(&s);
                    tip_round_trip(&m, &state.pose, &tip.position, &s.q);
                }
                Err(e) => message(&e),
            }
        }
        // The Jacobian's inverse and the margins at arbitrary joints.
        _ => {
            let q = Joints::new(inp.real(), inp.real(), inp.real());
            match m.jacobian_inverse(&q) {
                Ok(inv) => assert!(
                    inv.iter().all(|v| v.wide().is_finite()),
                    "jacobian_inverse: {inv:?} at {q:?}, geometry {:?} ({})",
                    m.geometry(),
                    T::NAME
                ),
                Err(e) => message(&e),
            }
        }
    }
}

/// The assumed module 1, or one with a guide, a node and the FK's stopping
/// rules chosen by the fuzzer.
fn parallel_geometry_in<T: FuzzFloat>(inp: &mut Input) -> ParallelGeometry<T> {
    let mut g = ParallelGeometry::<T>::assumed();
    if inp.flag() {
        let j = usize::from(inp.choose(6));
        if let Some(guide) = g.guides.get_mut(j) {
            guide.point = vector_in(inp);
            guide.direction = vector_in(inp);
            guide.link_length = inp.real();
            guide.encoder_offset = inp.real();
        }
        if let Some(node) = g.nodes.get_mut(usize::from(inp.choose(3))) {
            *node = vector_in(inp);
        }
        g.thresholds.serial = inp.real();
        g.thresholds.parallel = inp.real();
        g.fk = FkOptions {
            tolerance: inp.real(),
            max_iterations: u32::from(inp.byte()),
        };
    }
    g
}

fn module1_in<T: FuzzFloat>(inp: &mut Input) {
    let geometry = parallel_geometry_in::<T>(inp);
    let robot = match ParallelRobot::new(geometry) {
        Ok(r) => r,
        Err(e) => return message(&e),
    };
    let tolerance = robot.geometry().fk.tolerance;
    let pose = pose_in::<T>(inp);
    match inp.choose(3) {
        // IK, then FK back from a guess near the pose (or the pose itself).
        0 => {
            let q = match if inp.flag() {
                robot.ik(&pose)
            } else {
                robot.ik_unchecked(&pose)
            } {
                Ok(q) => q,
                Err(e) => return message(&e),
            };
            finite("IK", &q.0);
            let at = robot
                .residual(&pose, &q)
                .expect("finite pose and actuators");
            let eps = T::EPS;
            // The sizes involved: the platform's position against the
            // nodes, and each reading's offset against its link (the reading
            // `slider + o_j` rounds to the precision of `o_j`).
            let offsets = robot
                .geometry()
                .guides
                .iter()
                .map(|g| g.encoder_offset.wide().abs() / g.link_length.wide())
                .fold(0.0, f64::max);
            // And each leg's own sizes against its link: the IK puts slider
            // `j` where `|P + R a_i - B_j - u_j (q_j - o_j)| = l_j`, a
            // difference of numbers of the size of `|P|`, the node's `|a_i|`
            // and the guide's `|B_j|`, each rounded to its own precision; a
            // node or guide far from the rest (a fuzzed one) rounds away
            // more than its link's length times eps (an f32 node at 1e19 mm
            // holds a 350 mm link only to 1e12 mm), which `|P| / L` (`L` the
            // nodes' spread, 1e19 mm there) does not count.
            let p = norm(&pose.position());
            let legs = robot
                .geometry()
                .guides
                .iter()
                .enumerate()
                .map(|(j, g)| {
                    let a = norm(&robot.geometry().nodes[j / 2]);
                    (p + a + norm(&g.point)) / g.link_length.wide()
                })
                .fold(0.0, f64::max);
            let scale = 1.0 + p / robot.length_scale().wide() + offsets + legs;
            assert!(
                at.wide() <= 64.0 * eps * scale,
                "the IK's actuators {q:?} leave a residual {} at their own pose {pose:?} ({}), geometry {:?}",
                at.wide(),
                T::NAME,
                robot.geometry()
            );
            let offset: [T; 6] = inp.reals();
            let guess = Pose::from_array(core::array::from_fn(|i| {
                pose.to_array()[i] + offset[i] * T::of(1e-4)
            }));
            fk_checked(&robot, &q, &guess, tolerance);
        }
        // FK of arbitrary actuators from an arbitrary guess.
        1 => {
            let q = Actuators(inp.reals());
            fk_checked(&robot, &q, &pose, tolerance);
        }
        // The solve with rates and margins.
        _ => {
            let mut state = state_in::<T>(inp);
            state.pose = pose;
            match robot.solve_state(&state) {
                Ok(s) => parallel_solution_finite(&s),
                Err(e) => message(&e),
            }
        }
    }
}

/// FK from `guess`: an `Ok` pose is finite and holds the actuators within
/// the tolerance (recomputed by [`ParallelRobot::residual`]).
fn fk_checked<T: FuzzFloat>(
    robot: &ParallelRobot<T>,
    q: &Actuators<T>,
    guess: &Pose<T>,
    tolerance: T,
) {
    match robot.fk(q, guess) {
        Ok(sol) => {
            finite("FK pose", &sol.pose.to_array());
            assert!(
                sol.residual <= tolerance,
                "FK's residual {} above its tolerance {} ({})",
                sol.residual.wide(),
                tolerance.wide(),
                T::NAME
            );
            let r = robot
                .residual(&sol.pose, q)
                .expect("finite pose and actuators");
            // The residual recomputed at the rounded pose: the tolerance,
            // and the rounding of the residual's own terms.
            let slack =
                16.0 * T::EPS * (1.0 + norm(&sol.pose.position()) / robot.length_scale().wide());
            // In the FK's own measure: `residual` is `rho = max_j ||e_j| -
            // l_j| / l_j`, the tolerance bounds `||e_j|^2 - l_j^2| / (2
            // l_j^2)` (`FkOptions::tolerance`), that is `rho (2 - rho) / 2`
            // for `|e_j| = (1 - rho) l_j` and `rho (2 + rho) / 2` for `(1 +
            // rho) l_j`. The same to first order, apart for a large (fuzzed)
            // tolerance: 0.49 allows a link at a quarter of its length, a
            // `rho` of 0.75. The smaller is compared (the larger when `rho >
            // 1`, as `|e_j|` is not negative).
            let rho = r.wide();
            let measure = if rho <= 1.0 {
                rho * (2.0 - rho) / 2.0
            } else {
                rho * (2.0 + rho) / 2.0
            };
            assert!(
                measure <= tolerance.wide() + slack,
                "FK's pose leaves a residual {rho} ({measure} in the FK's measure) above the tolerance {} ({})",
                tolerance.wide(),
                T::NAME
            );
        }
        Err(e) => message(&e),
    }
}

fn controller_in<T: FuzzFloat>(inp: &mut Input) {
    let mut c = Controller::<T>::paper();
    if inp.flag() {
        c.modes = [AssemblyMode::B, AssemblyMode::A];
    }
    let tips = if inp.flag() {
        TipTargets::paper()
    } else {
        TipTargets {
            left: vector_in(inp),
            right: vector_in(inp),
        }
    };
    // A few cycles, so that the margin tracker's state carries over.
    let mut tracker = MarginTracker::new();
    for _ in 0..1 + inp.choose(3) {
        let state = state_in::<T>(inp);
        match c.step(&state, &tips, &mut tracker) {
            Ok(s) => {
                parallel_solution_finite(&s.module1);
                instrument_solution_finite(&s.left);
                instrument_solution_finite(&s.right);
                tip_round_trip(&c.left, &state.pose, &tips.left, &s.left.q);
                tip_round_trip(&c.right, &state.pose, &tips.right, &s.right.q);
            }
            Err(e) => message(&e),
        }
    }
}
