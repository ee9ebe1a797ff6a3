//! Statics (`parasils_kin::statics`) against truths from outside it: the
//! balance of power with the controller's own rates along the paper's turn,
//! the virtual work against central differences of the inverse and forward
//! kinematics, and loads whose forces follow by hand (symmetry, a force
//! along the tool).

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};
use parasils_kin::{
    Controller, Error, Instrument, Joints, Loads, MarginTracker, ParallelRobot, Payload,
    PlatformState, Pose, PoseRate, Real, Side, TipTargets, Wrench,
};

mod common;
use common::module1::{symmetric_pose, unlimited};
use common::motion::reorientation;

/// A small deterministic generator (SplitMix64) of numbers in `[-1, 1)`.
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn vector(&mut self, scale: f64) -> Vector3<f64> {
        Vector3::new(self.next(), self.next(), self.next()) * scale
    }

    /// A wrench of tens of N and thousands of N mm.
    fn wrench(&mut self) -> Wrench<f64> {
        Wrench::new(self.vector(20.0), self.vector(3000.0))
    }
}

/// The paper's turn, sampled every 50 ms over its 4.5 s, with the
/// controller's step at each instant.
fn paper_turn() -> impl Iterator<Item = (PlatformState<f64>, parasils_kin::ControlStep<f64>)> {
    let controller = Controller::<f64>::paper();
    let tips = TipTargets::paper();
    let mut tracker = MarginTracker::new();
    (0..=90).map(move |k| {
        let state = reorientation::<f64>(0.05 * k as f64);
        let step = controller
            .step(&state, &tips, &mut tracker)
            .expect("the paper's turn is regular");
        (state, step)
    })
}

#[test]
fn module1_power_balance_along_the_paper_turn() {
    let robot = ParallelRobot::<f64>::assumed();
    let mut rng = Numbers(1);
    let mut checked = 0;
    for (_, step) in paper_turn() {
        for _ in 0..10 {
            let w = rng.wrench();
            let f = robot
                .slider_forces(&step.frame, &step.module1, &w)
                .expect("regular");
            let actuators: f64 = (0..6).map(|j| f.force[j] * step.module1.q_dot[j]).sum();
            let scale: f64 = (0..6)
                .map(|j| (f.force[j] * step.module1.q_dot[j]).abs())
                .sum();
            let platform = w.power_on(&step.frame);
            if scale == 0.0 {
                // At rest (t = 0, 4.5 s): no power on either side.
                assert_eq!(platform, 0.0);
                continue;
            }
            let rel = (actuators - platform).abs() / scale;
            assert!(rel < 1e-12, "power {actuators} vs {platform}: {rel:e}");
            checked += 1;
        }
    }
    assert!(checked > 800);
}

/// The balance with a moving `P` too (motion type 1's `Pdot`), away from the
/// paper's turn.
#[test]
fn module1_power_balance_with_translation() {
    let robot = unlimited();
    let mut rng = Numbers(2);
    for _ in 0..200 {
        let p0 = Pose::<f64>::paper_start().to_array();
        let pose: [f64; 6] = core::array::from_fn(|i| {
            p0[i] + rng.next() * if i < 3 { 30.0 } else { 15f64.to_radians() }
        });
        let v: [f64; 6] = core::array::from_fn(|i| rng.next() * if i < 3 { 50.0 } else { 0.3 });
        let state = PlatformState {
            pose: Pose::from_array(pose),
            velocity: PoseRate::new(v[0], v[1], v[2], v[3], v[4], v[5]),
            acceleration: PoseRate::zero(),
        };
        let frame = state.frame().expect("finite");
        let solution = robot.solve(&frame).expect("regular");
        let w = rng.wrench();
        let f = robot.slider_forces(&frame, &solution, &w).expect("regular");
        let terms: [f64; 6] = core::array::from_fn(|j| f.force[j] * solution.q_dot[j]);
        let scale: f64 = terms.iter().map(|t| t.abs()).sum();
        let rel = (terms.iter().sum::<f64>() - w.power_on(&frame)).abs() / scale;
        assert!(rel < 1e-12, "{rel:e}");
    }
}

/// Each instrument module holds its tip still while the platform turns: the
/// joints' power cancels the platform's at the tip,
/// `tau_s . qs_dot = -F . (Pdot + omega_F x (p - P))`, with the module's own
/// rates.
#[test]
fn instrument_power_balance_along_the_paper_turn() {
    let controller = Controller::<f64>::paper();
    let tips = TipTargets::paper();
    let mut rng = Numbers(3);
    for (_, step) in paper_turn() {
        let omega_f = step.frame.rotation * step.frame.omega;
        for (module, solution, tip) in [
            (&controller.left, &step.left, tips.left),
            (&controller.right, &step.right, tips.right),
        ] {
            for _ in 0..10 {
                let force = rng.vector(15.0);
                let tau = module
                    .joint_forces(&step.frame.rotation, &solution.q, &force)
                    .expect("finite");
                let platform_at_tip =
                    step.frame.velocity + omega_f.cross(&(tip - step.frame.position));
                let joints = tau.power(&solution.q_dot);
                let expected = -force.dot(&platform_at_tip);
                let scale = (tau.qs1 * solution.q_dot.qs1).abs()
                    + (tau.qs2 * solution.q_dot.qs2).abs()
                    + (tau.qs3 * solution.q_dot.qs3).abs();
                if scale == 0.0 {
                    assert_eq!(expected, 0.0);
                    continue;
                }
                assert!(
                    (joints - expected).abs() / scale < 1e-12,
                    "{joints} vs {expected}"
                );
            }
        }
    }
}

/// The whole chain: the twelve actuators' power is the power the loads
/// receive: the held tips' none, the endoscope tip's `F . v` and the
/// weight's `-M g . v_com`, each from the point's own velocity.
#[test]
fn chain_power_balance_along_the_paper_turn() {
    let controller = Controller::<f64>::paper();
    let mut rng = Numbers(4);
    for (_, step) in paper_turn() {
        let payload = Payload::new(2.0 + rng.next(), rng.vector(80.0)).with_inertia(inertia());
        let loads = Loads {
            endoscope: rng.vector(5.0),
            endoscope_depth: 60.0,
            payload,
            ..Loads::tips(rng.vector(15.0), rng.vector(15.0))
        };
        let f = controller.forces(&step, &loads).expect("regular");
        let terms = [
            (0..6)
                .map(|j| f.module1.force[j] * step.module1.q_dot[j])
                .sum::<f64>(),
            f.left.power(&step.left.q_dot),
            f.right.power(&step.right.q_dot),
        ];
        let scale: f64 = (0..6)
            .map(|j| (f.module1.force[j] * step.module1.q_dot[j]).abs())
            .sum::<f64>()
            + terms[1].abs()
            + terms[2].abs();
        let scope_velocity = step.frame.point_velocity(&Vector3::new(0.0, 0.0, -60.0));
        let com_velocity = step.frame.point_velocity(&payload.com);
        let weight = payload.gravity * payload.mass / 1000.0;
        // The kinetic energy's rate: M a_c . v_c + omega . I alpha (the
        // gyroscopic term does no work), kg mm^2/s^3 = 1e-3 N mm/s.
        let a_com = step.frame.point_acceleration(&payload.com);
        let (w, a) = (step.frame.omega, step.frame.alpha);
        let kinetic =
            (payload.mass * a_com.dot(&com_velocity) + w.dot(&(payload.inertia * a))) / 1000.0;
        let expected = loads.endoscope.dot(&scope_velocity) - weight.dot(&com_velocity) + kinetic;
        if scale == 0.0 {
            assert_eq!(expected, 0.0);
            continue;
        }
        let rel = (terms.iter().sum::<f64>() - expected).abs() / scale;
        assert!(rel < 1e-12, "{rel:e}");
    }
}

/// An inertia tensor about the centre of mass, kg mm^2: a 2 kg body of
/// about 100 mm, its principal axes turned from the platform's.
fn inertia() -> Matrix3<f64> {
    Matrix3::new(
        2.0e4, 1.5e3, -8.0e2, 1.5e3, 3.0e4, 2.0e3, -8.0e2, 2.0e3, 1.5e4,
    )
}

/// The platform's dynamics against an independent derivation: the
/// generalised forces of Lagrange's equations on the pose coordinates
/// `(X, Y, Z, psi, theta, phi)`, `d/dt dL/dxdot - dL/dx` with
/// `L = M |v_c|^2 / 2 + omega . I omega / 2 + M g . p_c`, every derivative
/// taken numerically (five-point stencils), equal the Newton-Euler
/// wrench's generalised forces.
#[test]
fn the_newton_euler_wrench_is_lagranges() {
    let mut rng = Numbers(8);
    for case in 0..20 {
        let mut body = Payload::new(2.0 + rng.next(), rng.vector(80.0)).with_inertia(inertia());
        if case % 2 == 1 {
            // Without gravity the motion's terms are the whole of it.
            body.gravity = Vector3::zeros();
        }
        let p0 = Pose::<f64>::paper_start().to_array();
        let x0: [f64; 6] =
            core::array::from_fn(|i| p0[i] + rng.next() * if i < 3 { 30.0 } else { 0.3 });
        let v0: [f64; 6] = core::array::from_fn(|i| rng.next() * if i < 3 { 80.0 } else { 0.6 });
        let a0: [f64; 6] = core::array::from_fn(|i| rng.next() * if i < 3 { 500.0 } else { 2.0 });
        let state = |x: [f64; 6], v: [f64; 6], a: [f64; 6]| PlatformState {
            pose: Pose::from_array(x),
            velocity: PoseRate::new(v[0], v[1], v[2], v[3], v[4], v[5]),
            acceleration: PoseRate::new(a[0], a[1], a[2], a[3], a[4], a[5]),
        };
        // L in kg mm^2/s^2.
        let lagrangian = |x: [f64; 6], v: [f64; 6]| {
            let f = state(x, v, [0.0; 6]).frame().expect("finite");
            let v_c = f.point_velocity(&body.com);
            let w = f.omega;
            0.5 * body.mass * v_c.norm_squared()
                + 0.5 * w.dot(&(body.inertia * w))
                + body.mass * body.gravity.dot(&f.to_fixed(&body.com))
        };
        let stencil = |g: &dyn Fn(f64) -> f64, h: f64| {
            (g(-2.0 * h) - 8.0 * g(-h) + 8.0 * g(h) - g(2.0 * h)) / (12.0 * h)
        };
        let at = |t: f64| -> ([f64; 6], [f64; 6]) {
            (
                core::array::from_fn(|i| x0[i] + v0[i] * t + 0.5 * a0[i] * t * t),
                core::array::from_fn(|i| v0[i] + a0[i] * t),
            )
        };
        let frame = state(x0, v0, a0).frame().expect("finite");
        let expected = body
            .moving_wrench(&frame)
            .on_pose_coordinates(&Pose::from_array(x0));
        let norm = expected.iter().map(|q| q * q).sum::<f64>().sqrt();
        for k in 0..6 {
            // dL/dxdot_k at time t (L is quadratic in the rates: the
            // stencil is exact there up to rounding).
            let momentum = |t: f64| {
                let (x, v) = at(t);
                stencil(
                    &|d| {
                        let mut v = v;
                        v[k] += d;
                        lagrangian(x, v)
                    },
                    if k < 3 { 1.0 } else { 0.01 },
                )
            };
            let d_momentum = stencil(&momentum, 2e-3);
            let d_position = stencil(
                &|d| {
                    let mut x = x0;
                    x[k] += d;
                    lagrangian(x, v0)
                },
                if k < 3 { 1e-2 } else { 1e-4 },
            );
            let lagrange = (d_momentum - d_position) / 1000.0;
            let rel = (lagrange - expected[k]).abs() / norm;
            assert!(
                rel < 1e-8,
                "case {case}, x{k}: {lagrange} vs {}: {rel:e}",
                expected[k]
            );
        }
        // At rest it is the weight's holding wrench.
        let rest = PlatformState::at_rest(Pose::from_array(x0))
            .frame()
            .expect("finite");
        let (a, b) = (body.moving_wrench(&rest), body.holding_wrench(&rest));
        assert!((a.force - b.force).norm() + (a.moment - b.moment).norm() < 1e-12);
    }
}

/// Virtual work: `sum_j tau_j dq_j/dx_k` by central differences of the IK
/// equals the wrench's generalised force on each pose coordinate `x_k`
/// (`X_P, Y_P, Z_P, psi, theta, phi`).
#[test]
fn module1_virtual_work_against_finite_differences_of_the_ik() {
    let robot = unlimited();
    let mut rng = Numbers(5);
    let p0 = Pose::<f64>::paper_start().to_array();
    for case in 0..50 {
        let pose: [f64; 6] = if case == 0 {
            p0
        } else {
            core::array::from_fn(|i| {
                p0[i] + rng.next() * if i < 3 { 30.0 } else { 20f64.to_radians() }
            })
        };
        let w = rng.wrench();
        let f = robot.statics(&Pose::from_array(pose), &w).expect("regular");
        let q_at = |k: usize, h: f64| {
            let mut x = pose;
            x[k] += h;
            robot.ik(&Pose::from_array(x)).expect("in reach").0
        };
        let generalised = w.on_pose_coordinates(&Pose::from_array(pose));
        let norm = generalised.iter().map(|g| g * g).sum::<f64>().sqrt();
        for (k, expected) in generalised.iter().enumerate() {
            let h = if k < 3 { 1e-3 } else { 1e-5 };
            let (plus, minus) = (q_at(k, h), q_at(k, -h));
            let fd: f64 = (0..6)
                .map(|j| f.force[j] * (plus[j] - minus[j]) / (2.0 * h))
                .sum();
            let rel = (fd - expected).abs() / norm;
            assert!(rel < 1e-7, "case {case}, x{k}: {fd} vs {expected}: {rel:e}");
        }
    }
}

/// Virtual work of an instrument module: `tau_k = F . d p / d qs_k` by
/// central differences of the forward kinematics, the platform turned.
#[test]
fn instrument_virtual_work_against_finite_differences_of_the_fk() {
    let mut rng = Numbers(6);
    for side in [Side::Left, Side::Right] {
        let module = Instrument::<f64>::paper(side);
        for _ in 0..100 {
            let pose = Pose::from_array(core::array::from_fn(|i| {
                rng.next() * if i < 3 { 50.0 } else { 0.5 }
            }));
            let q = Joints::new(rng.next(), 0.8 * rng.next(), 150.0 + 100.0 * rng.next());
            let force = rng.vector(15.0);
            let tau = module
                .joint_forces(&pose.rotation(), &q, &force)
                .expect("finite")
                .to_array();
            let scale = tau.iter().map(|t| t.abs()).fold(0.0, f64::max);
            for k in 0..3 {
                let h = if k < 2 { 1e-6 } else { 1e-4 };
                let at = |d: f64| {
                    let mut x = q.to_array();
                    x[k] += d;
                    module
                        .fk(&pose, &Joints::new(x[0], x[1], x[2]))
                        .expect("finite")
                };
                let fd = force.dot(&(at(h) - at(-h))) / (2.0 * h);
                assert!(
                    (fd - tau[k]).abs() / scale < 1e-7,
                    "{side:?} qs{}: {fd} vs {}",
                    k + 1,
                    tau[k]
                );
            }
        }
    }
}

/// By hand: at the symmetric pose the guides point down (`u = -z`) and the
/// three legs are alike, so a vertical force `F_z` on `P` loads every link
/// equally, `lambda e_j` with the same `lambda`, and each slider carries
/// `tau_j = -F_z / 6`; a 2 kg mass below `P` is the same case with
/// `F_z = 2 * 9.81` N.
#[test]
fn a_vertical_force_at_the_symmetric_pose_is_shared_equally() {
    let robot = ParallelRobot::<f64>::assumed();
    let pose = symmetric_pose::<f64>();
    let f = robot
        .statics(
            &pose,
            &Wrench::new(Vector3::new(0.0, 0.0, -30.0), Vector3::zeros()),
        )
        .expect("regular");
    for j in 0..6 {
        assert!(
            (f.force[j] - 5.0).abs() < 1e-12,
            "q{}: {}",
            j + 1,
            f.force[j]
        );
        assert!((f.link[j] - f.link[0]).abs() < 1e-12);
    }
    // The link is longer than its vertical share: sigma = tau l / |e_z|.
    let q = robot.ik(&pose).expect("in reach");
    let g = &robot.geometry().guides[0];
    let node = pose.rotation() * robot.geometry().nodes[0] + pose.position();
    let e = node - g.point - g.direction * q[0];
    assert!((f.link[0] - 5.0 * 350.0 / e.z.abs()).abs() < 1e-9);
    // A 2 kg mass on the platform's axis: the same case with F_z = 19.62 N up.
    let frame = PlatformState::at_rest(pose).frame().expect("finite");
    let hold = Payload::new(2.0, Vector3::new(0.0, 0.0, -100.0)).holding_wrench(&frame);
    assert!((hold.force - Vector3::new(0.0, 0.0, 19.62)).norm() < 1e-12);
    assert!(hold.moment.norm() < 1e-12);
    let f = robot.statics(&pose, &hold).expect("regular");
    assert!(
        f.force
            .0
            .iter()
            .all(|tau| (tau + 19.62 / 6.0).abs() < 1e-12)
    );
}

/// By hand: a force along the tool moves only the insertion joint: the
/// whole force on `qs3` and no torque (the first two columns of `J` are
/// across the tool); a force across the tool at distance `qs3` from the RCM
/// along the tip's path for `qs2` needs the torque `|F|` times that path's
/// radius, `qs3 cos(beta)`.
#[test]
fn a_force_along_the_tool_loads_only_the_insertion() {
    let pose = Pose::<f64>::paper_start();
    for side in [Side::Left, Side::Right] {
        let module = Instrument::<f64>::paper(side);
        let q = Joints::new(0.3, -0.4, 140.0);
        let inwards = pose.rotation() * module.fk_local(&q) / q.qs3;
        let tau = module
            .joint_forces(&pose.rotation(), &q, &(inwards * 12.0))
            .expect("finite");
        assert!((tau.qs3 - 12.0).abs() < 1e-12);
        assert!(tau.qs1.abs() < 1e-10 && tau.qs2.abs() < 1e-10);
        // Across the tool, along the tip's motion for qs2 alone.
        let across = pose.rotation() * module.jacobian(&q).column(1);
        let across = across / across.norm();
        let tau = module
            .joint_forces(&pose.rotation(), &q, &(across * 3.0))
            .expect("finite");
        let radius = module.jacobian(&q).column(1).norm();
        assert!((tau.qs2 - 3.0 * radius).abs() < 1e-9);
        assert!(tau.qs3.abs() < 1e-12);
        // qs2 turns the tool on a cone of half-angle 90 deg - beta about
        // its axis: the tip, qs3 from the RCM, moves qs3 cos(beta) per rad.
        assert!((radius - q.qs3 * 10f64.to_radians().cos()).abs() < 1e-9);
    }
}

/// The force transmission is at least the parallel margin and reaches it on
/// the wrench that the weakest direction needs: `W_s = v_min`, the right
/// singular vector of the smallest singular value of `J_s^T`.
#[test]
fn the_transmission_is_bounded_by_the_parallel_margin() {
    let robot = ParallelRobot::<f64>::assumed();
    let pose = Pose::<f64>::paper_start();
    let margin = robot.margins(&pose).expect("in reach").parallel;
    let mut rng = Numbers(7);
    for _ in 0..500 {
        let f = robot.statics(&pose, &rng.wrench()).expect("regular");
        assert!(f.transmission >= margin * (1.0 - 1e-12));
    }
    let js: Matrix6<f64> = robot.jacobian(&pose).expect("in reach");
    let svd = js.svd(true, true);
    let (k, s_min) = svd.singular_values.argmin();
    assert!((s_min - margin).abs() < 1e-12);
    // J_s = U S V^T: J_s^T u_k = s_k v_k, so the wrench v_k needs u_k / s_k.
    let v: Vector6<f64> = svd.v_t.expect("computed").row(k).transpose();
    let l = robot.length_scale();
    let w = Wrench::new(
        Vector3::new(v[0], v[1], v[2]),
        Vector3::new(v[3], v[4], v[5]) * l,
    );
    let f = robot.statics(&pose, &w).expect("regular");
    assert!((f.transmission - margin).abs() < 1e-10 * margin);
    let u = svd.u.expect("computed").column(k).into_owned();
    let sign = f.link[0].signum() * u[0].signum();
    for j in 0..6 {
        assert!((f.link[j] - sign * u[j] / s_min).abs() < 1e-9 / s_min);
    }
    assert_eq!(
        robot
            .statics(&pose, &Wrench::zero())
            .expect("regular")
            .transmission,
        1.0
    );
}

#[test]
fn near_the_parallel_singularity_the_forces_are_an_error() {
    let mut g = *ParallelRobot::<f64>::assumed().geometry();
    let margin = ParallelRobot::<f64>::assumed()
        .margins(&Pose::paper_start())
        .expect("in reach")
        .parallel;
    g.thresholds.parallel_command = margin * 1.01;
    let robot = ParallelRobot::new(g).expect("valid");
    let frame = PlatformState::at_rest(Pose::paper_start())
        .frame()
        .expect("finite");
    // A solution whose margin says the pose is too close.
    let mut solution = ParallelRobot::<f64>::assumed()
        .solve(&frame)
        .expect("regular");
    solution.margins.parallel = margin;
    match robot.slider_forces(&frame, &solution, &Wrench::zero()) {
        Err(Error::ParallelSingular {
            margin: m,
            threshold,
        }) => {
            assert_eq!(m, margin);
            assert_eq!(threshold, margin * 1.01);
        }
        other => panic!("expected ParallelSingular, got {other:?}"),
    }
    assert!(matches!(
        robot.statics(&Pose::paper_start(), &Wrench::zero()),
        Err(Error::ParallelSingular { .. })
    ));
}

#[test]
fn a_load_that_is_not_a_number_is_named() {
    let controller = Controller::<f64>::paper();
    let (_, step) = paper_turn().nth(30).expect("a sample");
    let loads = Loads::tips(Vector3::new(0.0, f64::NAN, 0.0), Vector3::zeros());
    match controller.forces(&step, &loads) {
        Err(Error::NonFinite { what, .. }) => assert_eq!(what, "loads.left.y"),
        other => panic!("expected NonFinite, got {other:?}"),
    }
    let wrench = Wrench::new(Vector3::zeros(), Vector3::new(f64::INFINITY, 0.0, 0.0));
    assert!(matches!(
        controller
            .module1
            .slider_forces(&step.frame, &step.module1, &wrench),
        Err(Error::NonFinite {
            what: "wrench.moment.x",
            ..
        })
    ));
}

/// The twelve forces in the order of the actuators' limits, and the first
/// beyond its limit named.
#[test]
fn forces_are_checked_against_the_actuators_limits() {
    let controller = Controller::<f64>::paper();
    let (_, step) = paper_turn().nth(30).expect("a sample");
    let f = controller
        .forces(
            &step,
            &Loads::tips(Vector3::new(0.0, 0.0, -10.0), Vector3::zeros()),
        )
        .expect("regular");
    let a = f.to_array();
    assert_eq!(a[..6], f.module1.force.0);
    assert_eq!(a[6..9], f.left.to_array());
    assert_eq!(a[9..], f.right.to_array());
    assert!(controller.limits.check_forces(&a).is_ok());
    // Ten times the load: ten times the forces (statics is linear), and
    // the left insertion, 10 N along the tool at most, now beyond 40 N.
    let g = controller
        .forces(
            &step,
            &Loads::tips(Vector3::new(0.0, 0.0, -100.0), Vector3::zeros()),
        )
        .expect("regular");
    for (x, y) in g.to_array().iter().zip(&a) {
        assert!((x - 10.0 * y).abs() <= 1e-12 * x.abs().max(1.0));
    }
    assert!(a[8].abs() <= 10.0 && g.to_array()[8].abs() > 40.0);
    // The first actuator beyond its limit, in the order of the twelve.
    let g = g.to_array();
    let first = (0..12)
        .find(|&k| g[k].abs() > controller.limits.force[k])
        .expect("one is beyond");
    let e = controller.limits.check_forces(&g).expect_err("beyond");
    let name = parasils_kin::Actuator::ALL[first].to_string();
    assert!(e.to_string().starts_with(&format!("{name}: ")), "{e}");
}

/// `f32`: the same balance of power, to single precision.
#[test]
fn f32_power_balance_along_the_paper_turn() {
    let controller = Controller::<f32>::paper();
    let tips = TipTargets::paper();
    let mut tracker = MarginTracker::new();
    let loads = Loads::<f32>::tips(Vector3::new(5.0, -3.0, 8.0), Vector3::new(-2.0, 4.0, 10.0));
    for k in 1..90 {
        let state = reorientation::<f32>(0.05 * k as f64);
        let step = controller
            .step(&state, &tips, &mut tracker)
            .expect("regular");
        let f = controller.forces(&step, &loads).expect("regular");
        let module1: f32 = (0..6)
            .map(|j| f.module1.force[j] * step.module1.q_dot[j])
            .sum();
        let scale: f32 = (0..6)
            .map(|j| (f.module1.force[j] * step.module1.q_dot[j]).abs())
            .sum();
        let rel = (module1 - f.platform.power_on(&step.frame)).abs() / scale;
        assert!(rel < 2e-4, "t = {}: {rel:e}", 0.05 * k as f64);
        let total = module1 + f.left.power(&step.left.q_dot) + f.right.power(&step.right.q_dot);
        assert!(total.abs() / scale < 2e-4, "{}", total.to_f64());
    }
}

/// The Euler-angle increments `(dpsi, dtheta, dphi)` that turn the platform
/// at `pose` by the small fixed-frame rotation vector `dtheta_f` (rad), to
/// first order: `dtheta_f = R E de`, `E` the Euler rates' map to `omega`.
fn euler_increments(pose: &Pose<f64>, dtheta_f: &Vector3<f64>) -> Vector3<f64> {
    let (s2, c2) = pose.theta.sin_cos();
    let (s3, c3) = pose.phi.sin_cos();
    let e = Matrix3::new(c2 * c3, s3, 0.0, -c2 * s3, c3, 0.0, s2, 0.0, 1.0);
    (pose.rotation() * e).try_inverse().expect("regular") * dtheta_f
}

/// The platform's displacement under a load, against central differences
/// of the IK: moving the platform by it changes each actuator by the
/// slider's give, `tau_j / k_j`; and the stiffness matrix maps it back to
/// the load.
#[test]
fn module1_displacement_against_the_ik() {
    let robot = unlimited();
    let k = [180.0, 220.0, 200.0, 150.0, 260.0, 210.0];
    let mut rng = Numbers(9);
    for _ in 0..30 {
        let p0 = Pose::<f64>::paper_start().to_array();
        let pose = Pose::from_array(core::array::from_fn(|i| {
            p0[i] + rng.next() * if i < 3 { 30.0 } else { 0.3 }
        }));
        let frame = PlatformState::at_rest(pose).frame().expect("finite");
        let solution = robot.solve(&frame).expect("regular");
        let load = rng.wrench();
        let (dp, dth) = robot
            .displacement(&frame, &solution, &load, &k)
            .expect("regular");
        let tau = robot
            .slider_forces(&frame, &solution, &load)
            .expect("regular")
            .force;
        let de = euler_increments(&pose, &dth);
        let dx = [dp.x, dp.y, dp.z, de.x, de.y, de.z];
        let eps = 1e-3;
        let q_at = |s: f64| {
            let x = pose.to_array();
            robot
                .ik(&Pose::from_array(core::array::from_fn(|i| {
                    x[i] + s * dx[i]
                })))
                .expect("in reach")
                .0
        };
        let (plus, minus) = (q_at(eps), q_at(-eps));
        let scale = (0..6).fold(0f64, |m, j| m.max((tau[j] / k[j]).abs()));
        for j in 0..6 {
            let fd = (plus[j] - minus[j]) / (2.0 * eps);
            assert!(
                (fd - tau[j] / k[j]).abs() < 1e-7 * scale,
                "q{}: {fd} vs {}",
                j + 1,
                tau[j] / k[j]
            );
        }
        // K_x (dP, dtheta_F) = load.
        let kx = robot
            .platform_stiffness(&frame, &solution, &k)
            .expect("regular");
        let w = kx * Vector6::new(dp.x, dp.y, dp.z, dth.x, dth.y, dth.z);
        let expected = Vector6::new(
            load.force.x,
            load.force.y,
            load.force.z,
            load.moment.x,
            load.moment.y,
            load.moment.z,
        );
        assert!((w - expected).norm() < 1e-9 * expected.norm());
        assert!((kx - kx.transpose()).norm() < 1e-9 * kx.norm());
    }
}

/// By hand: at the symmetric pose a vertical load `W_z` on `P` is shared
/// by the six sliders, `-W_z / 6` each along `u = -z`, so each gives way by
/// `-W_z / (6 k)` along `u`, and the platform drops or rises with them:
/// `dZ = W_z / (6 k)`, no turn.
#[test]
fn a_vertical_load_at_the_symmetric_pose_moves_the_platform_straight() {
    let robot = ParallelRobot::<f64>::assumed();
    let frame = PlatformState::at_rest(symmetric_pose())
        .frame()
        .expect("finite");
    let solution = robot.solve(&frame).expect("regular");
    let load = Wrench::new(Vector3::new(0.0, 0.0, -60.0), Vector3::zeros());
    let (dp, dth) = robot
        .displacement(&frame, &solution, &load, &[200.0; 6])
        .expect("regular");
    assert!((dp - Vector3::new(0.0, 0.0, -0.05)).norm() < 1e-12, "{dp}");
    assert!(dth.norm() < 1e-15);
    assert!(matches!(
        robot.displacement(&frame, &solution, &load, &[200.0, 0.0, 1.0, 1.0, 1.0, 1.0]),
        Err(Error::InvalidParameter {
            what: "stiffness",
            ..
        })
    ));
}

/// A tip's deflection: against central differences of the FK with the
/// platform and the joints moved by their gives, symmetric between two
/// forces (Maxwell-Betti) and along the force.
#[test]
fn tip_deflection_against_the_fk_and_reciprocal() {
    let controller = Controller::<f64>::paper();
    let stiffness = parasils_kin::ActuatorStiffness::assumed();
    let k = stiffness.stiffness;
    let mut rng = Numbers(10);
    for (state, step) in paper_turn().step_by(9) {
        for (side, module, q, base) in [
            (Side::Left, &controller.left, step.left.q, 6),
            (Side::Right, &controller.right, step.right.q, 9),
        ] {
            let force = rng.vector(10.0);
            let d = controller
                .tip_deflection(&step, side, &force, &stiffness)
                .expect("regular");
            assert!(force.dot(&d) > 0.0);
            // The gives: the platform's and the joints'.
            let tip = step.frame.to_fixed(&module.fk_platform(&q));
            let load = Wrench::at(&force, &tip, &step.frame.position);
            let slider_k = [k[0], k[1], k[2], k[3], k[4], k[5]];
            let (dp, dth) = controller
                .module1
                .displacement(&step.frame, &step.module1, &load, &slider_k)
                .expect("regular");
            let tau = module
                .joint_forces(&step.frame.rotation, &q, &force)
                .expect("finite");
            let dqs = [
                tau.qs1 / k[base],
                tau.qs2 / k[base + 1],
                tau.qs3 / k[base + 2],
            ];
            let de = euler_increments(&state.pose, &dth);
            let dx = [dp.x, dp.y, dp.z, de.x, de.y, de.z];
            let eps = 1e-3;
            let tip_at = |s: f64| {
                let x = state.pose.to_array();
                let pose = Pose::from_array(core::array::from_fn(|i| x[i] + s * dx[i]));
                let qs = Joints::new(q.qs1 + s * dqs[0], q.qs2 + s * dqs[1], q.qs3 + s * dqs[2]);
                module.fk(&pose, &qs).expect("finite")
            };
            let fd = (tip_at(eps) - tip_at(-eps)) / (2.0 * eps);
            assert!((fd - d).norm() < 1e-7 * d.norm(), "{side:?}: {fd} vs {d}");
            // Reciprocity: a . d(b) = b . d(a).
            let b = rng.vector(10.0);
            let db = controller
                .tip_deflection(&step, side, &b, &stiffness)
                .expect("regular");
            assert!((force.dot(&db) - b.dot(&d)).abs() < 1e-10 * force.norm() * db.norm());
        }
    }
}
