//! The spherical instrument modules against independent truths: the check
//! values of `docs/model.md` (*Check values*), round trips, finite
//! differences, mirror symmetry, and every error path.

use nalgebra::{Matrix3, Vector3};
use parasils_kin::error::{Error, InstrumentSingularity, Joint};
use parasils_kin::instrument::{InstrumentGeometry, JointLimits};
use parasils_kin::{
    AssemblyMode, Instrument, Joints, PlatformFrame, PlatformState, Pose, PoseRate, Real, Side,
    TipMotion,
};
use proptest::prelude::*;

const P0_TIP_LEFT: [f64; 3] = [50.0, -50.0, -620.0];

fn unlimited<T: Real>(side: Side) -> Instrument<T> {
    let mut g = InstrumentGeometry::paper(side);
    g.limits = JointLimits::unlimited();
    Instrument::new(g).expect("valid geometry")
}

fn deg3(q: &Joints<f64>) -> [f64; 3] {
    [q.qs1.to_degrees(), q.qs2.to_degrees(), q.qs3]
}

fn assert_joints_deg(q: &Joints<f64>, expected: [f64; 3], what: &str) {
    let got = deg3(q);
    for i in 0..3 {
        // The check values have four decimals.
        assert!(
            (got[i] - expected[i]).abs() < 5e-5,
            "{what}: got {got:?}, expected {expected:?}"
        );
    }
}

/// `a - b` wrapped to `(-pi, pi]`.
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(core::f64::consts::TAU);
    if d > core::f64::consts::PI {
        d - core::f64::consts::TAU
    } else {
        d
    }
}

mod check_values {
    use super::*;
    use parasils_kin::TipTargets;

    #[test]
    fn left_at_p0_both_modes() {
        let left = Instrument::<f64>::paper(Side::Left);
        let tip = Vector3::from(P0_TIP_LEFT);
        let [a, b] = left
            .ik_solutions(&Pose::paper_start(), &tip)
            .expect("reachable");
        assert_joints_deg(&a, [3.0889, -38.8695, 147.7687], "left mode A at P0");
        assert_joints_deg(&b, [-151.3897, -141.1305, 147.7687], "left mode B at P0");
        // Mode B is outside the default qs2 limits.
        assert!(matches!(
            left.ik(&Pose::paper_start(), &tip, AssemblyMode::B),
            Err(Error::JointLimit {
                side: Side::Left,
                joint: Joint::Qs1 | Joint::Qs2,
                ..
            })
        ));
    }

    #[test]
    fn the_mirrored_right_tip_has_the_same_joints() {
        let tips = TipTargets::<f64>::mirrored();
        let expected = Vector3::new(-9.6103, 53.9889, -636.9821);
        assert!((tips.right - expected).norm() < 1e-4, "{:?}", tips.right);
        let right = Instrument::<f64>::paper(Side::Right);
        let q = right
            .ik(&Pose::paper_start(), &tips.right, AssemblyMode::A)
            .expect("reachable");
        assert_joints_deg(&q, [3.0889, -38.8695, 147.7687], "right mode A at P0");
    }

    /// The default right tip: the mirror moved 35 mm along `X'` and 100 mm
    /// along `Y'` at `P0` (the value from an independent computation of
    /// `P + R (S R^T (left - P) + shift)`), reachable in mode A, and the
    /// joints found give the tip back by forward kinematics.
    #[test]
    fn the_default_right_tip_is_reachable() {
        let tips = TipTargets::<f64>::paper();
        let expected = Vector3::new(92.9107, 68.3284, -659.5392);
        assert!((tips.right - expected).norm() < 1e-4, "{:?}", tips.right);
        let right = Instrument::<f64>::paper(Side::Right);
        for pose in [
            Pose::paper_start(),
            Pose::from_mm_deg(15.0, 20.0, -500.0, 0.0, 35.0, -60.0),
        ] {
            let q = right
                .ik(&pose, &tips.right, AssemblyMode::A)
                .expect("reachable");
            let tip = right.fk(&pose, &q).expect("finite");
            assert!((tip - tips.right).norm() < 1e-9);
        }
    }

    #[test]
    fn both_modules_at_the_end_of_the_increments_reading() {
        let end = Pose::<f64>::from_mm_deg(15.0, 20.0, -500.0, 0.0, 35.0, -60.0);
        let tips = TipTargets::<f64>::mirrored();
        let left = Instrument::paper(Side::Left)
            .ik(&end, &tips.left, AssemblyMode::A)
            .expect("left reachable");
        let right = Instrument::paper(Side::Right)
            .ik(&end, &tips.right, AssemblyMode::A)
            .expect("right reachable");
        assert_joints_deg(&left, [20.7942, -61.8435, 151.0378], "left at the end");
        assert_joints_deg(&right, [18.5977, -13.0799, 143.6301], "right at the end");
    }

    #[test]
    fn f32_agrees_with_the_check_values() {
        let left = Instrument::<f32>::paper(Side::Left);
        let tip = Vector3::new(50.0f32, -50.0, -620.0);
        let q = left
            .ik(&Pose::paper_start(), &tip, AssemblyMode::A)
            .expect("reachable");
        assert!((q.qs1.to_degrees() - 3.0889).abs() < 1e-3);
        assert!((q.qs2.to_degrees() + 38.8695).abs() < 1e-3);
        assert!((q.qs3 - 147.7687).abs() < 2e-3);
    }
}

/// A random configuration of the domain of the acceptance checks.
#[derive(Debug, Clone, Copy)]
struct Case {
    pose: [f64; 6],
    q: [f64; 3],
}

/// Joints: `qs1` in `(-180, 180]` deg, `|qs2| <= 80` deg (mapped to mode B by
/// `qs2 -> 180 - qs2`), `qs3` in `[10, 400]` mm. Poses within 100 mm and
/// 45 deg of `P0`, per coordinate.
fn case() -> impl Strategy<Value = Case> {
    (
        prop::array::uniform3(-100.0f64..=100.0),
        prop::array::uniform3(-45.0f64..=45.0),
        -180.0f64..=180.0,
        -80.0f64..=80.0,
        10.0f64..=400.0,
    )
        .prop_map(|(dp, da, qs1, qs2, qs3)| {
            let p0 = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];
            Case {
                pose: [
                    p0[0] + dp[0],
                    p0[1] + dp[1],
                    p0[2] + dp[2],
                    (p0[3] + da[0]).to_radians(),
                    (p0[4] + da[1]).to_radians(),
                    (p0[5] + da[2]).to_radians(),
                ],
                q: [qs1.to_radians(), qs2.to_radians(), qs3],
            }
        })
}

fn joints_in_mode(q: [f64; 3], mode: AssemblyMode) -> Joints<f64> {
    match mode {
        AssemblyMode::A => Joints::new(q[0], q[1], q[2]),
        AssemblyMode::B => {
            let pi = core::f64::consts::PI;
            let qs2 = if q[1] >= 0.0 { pi - q[1] } else { -pi - q[1] };
            Joints::new(q[0], qs2, q[2])
        }
    }
}

fn cast_pose<T: Real>(p: [f64; 6]) -> Pose<T> {
    Pose::from_array(p.map(T::lit))
}

fn cast_joints<T: Real>(q: &Joints<f64>) -> Joints<T> {
    Joints::new(T::lit(q.qs1), T::lit(q.qs2), T::lit(q.qs3))
}

/// `FK(IK(x))` and `IK(FK(q))` for both modules and both modes in `T`;
/// returns the largest tip error (mm), angle error (rad) and `qs3` error (mm).
fn round_trips<T: Real>(c: &Case) -> (f64, f64, f64) {
    let pose = cast_pose::<T>(c.pose);
    let (mut tip_err, mut ang_err, mut len_err) = (0.0f64, 0.0f64, 0.0f64);
    for side in [Side::Left, Side::Right] {
        let m = unlimited::<T>(side);
        for mode in [AssemblyMode::A, AssemblyMode::B] {
            let q64 = joints_in_mode(c.q, mode);
            let q = cast_joints::<T>(&q64);
            let x = m.fk(&pose, &q).expect("finite");
            let back = m.ik(&pose, &x, mode).expect("reachable");
            assert_eq!(AssemblyMode::of(&back), mode);
            let x2 = m.fk(&pose, &back).expect("finite");
            tip_err = tip_err.max((x2 - x).map(|v| v.to_f64()).norm());
            ang_err = ang_err
                .max(angle_diff(back.qs1.to_f64(), q.qs1.to_f64()).abs())
                .max(angle_diff(back.qs2.to_f64(), q.qs2.to_f64()).abs());
            len_err = len_err.max((back.qs3.to_f64() - q.qs3.to_f64()).abs());
        }
    }
    (tip_err, ang_err, len_err)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100_000))]

    #[test]
    fn round_trips_f64(c in case()) {
        let (tip, ang, len) = round_trips::<f64>(&c);
        prop_assert!(tip < 1e-9, "FK(IK(x)) off by {tip} mm");
        prop_assert!(ang < 1e-9, "IK(FK(q)) off by {ang} rad");
        prop_assert!(len < 1e-9, "IK(FK(q)) off by {len} mm");
    }

    #[test]
    fn round_trips_f32(c in case()) {
        let (tip, ang, len) = round_trips::<f32>(&c);
        prop_assert!(tip < 2e-3, "FK(IK(x)) off by {tip} mm");
        prop_assert!(ang < 1e-4, "IK(FK(q)) off by {ang} rad");
        prop_assert!(len < 2e-3, "IK(FK(q)) off by {len} mm");
    }
}

/// A general motion for the finite-difference checks: every platform
/// coordinate and every tip coordinate moves as a quadratic in `t`, so that
/// the rates at `t = 0` are exactly the given ones.
#[derive(Debug, Clone, Copy)]
struct Motion {
    case: Case,
    pose_rate: [f64; 6],
    pose_acc: [f64; 6],
    tip_rate: [f64; 3],
    tip_acc: [f64; 3],
}

fn motion() -> impl Strategy<Value = Motion> {
    (
        case(),
        prop::array::uniform6(-1.0f64..=1.0),
        prop::array::uniform6(-1.0f64..=1.0),
        prop::array::uniform3(-20.0f64..=20.0),
        prop::array::uniform3(-20.0f64..=20.0),
    )
        .prop_map(|(case, r, a, tip_rate, tip_acc)| Motion {
            case,
            // mm/s and rad/s of the order of the paper's (tens of mm/s, 0.2 rad/s).
            pose_rate: [20.0 * r[0], 20.0 * r[1], 20.0 * r[2], r[3], r[4], r[5]],
            pose_acc: [20.0 * a[0], 20.0 * a[1], 20.0 * a[2], a[3], a[4], a[5]],
            tip_rate,
            tip_acc,
        })
}

impl Motion {
    fn state(&self, t: f64) -> PlatformState<f64> {
        let p = core::array::from_fn(|i| {
            self.case.pose[i] + self.pose_rate[i] * t + 0.5 * self.pose_acc[i] * t * t
        });
        let v: [f64; 6] = core::array::from_fn(|i| self.pose_rate[i] + self.pose_acc[i] * t);
        let a = self.pose_acc;
        PlatformState {
            pose: Pose::from_array(p),
            velocity: PoseRate::new(v[0], v[1], v[2], v[3], v[4], v[5]),
            acceleration: PoseRate::new(a[0], a[1], a[2], a[3], a[4], a[5]),
        }
    }

    fn tip(&self, m: &Instrument<f64>, mode: AssemblyMode, t: f64) -> TipMotion<f64> {
        let q0 = joints_in_mode(self.case.q, mode);
        let x0 = m.fk(&self.state(0.0).pose, &q0).expect("finite");
        let v = Vector3::from(self.tip_rate);
        let a = Vector3::from(self.tip_acc);
        TipMotion {
            position: x0 + v * t + a * (0.5 * t * t),
            velocity: v + a * t,
            acceleration: a,
        }
    }
}

/// The largest relative error of the analytic rates against central
/// differences, `|fd - analytic|_inf / max(|analytic|_inf, floor)`.
fn rel_err(fd: &Vector3<f64>, analytic: &Vector3<f64>, floor: f64) -> f64 {
    (fd - analytic).amax() / analytic.amax().max(floor)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn jacobian_matches_finite_differences(c in case()) {
        let h = 1e-6;
        for side in [Side::Left, Side::Right] {
            let m = unlimited::<f64>(side);
            for mode in [AssemblyMode::A, AssemblyMode::B] {
                let q = joints_in_mode(c.q, mode).to_vector();
                let j = m.jacobian(&Joints::from_vector(&q));
                let mut fd = Matrix3::zeros();
                for k in 0..3 {
                    let mut dq = Vector3::zeros();
                    dq[k] = h;
                    let plus = m.fk_local(&Joints::from_vector(&(q + dq)));
                    let minus = m.fk_local(&Joints::from_vector(&(q - dq)));
                    fd.set_column(k, &((plus - minus) / (2.0 * h)));
                }
                let err = (fd - j).amax() / j.amax();
                prop_assert!(err < 1e-6, "{side} {mode:?}: relative error {err}");
            }
        }
    }

    #[test]
    fn rates_match_finite_differences(mo in motion()) {
        let h = 1e-5;
        for side in [Side::Left, Side::Right] {
            let m = unlimited::<f64>(side);
            for mode in [AssemblyMode::A, AssemblyMode::B] {
                let at = |t: f64| {
                    m.solve(&PlatformFrame::new(&mo.state(t)), &mo.tip(&m, mode, t), mode)
                        .expect("regular")
                };
                let (minus, mid, plus) = (at(-h), at(0.0), at(h));
                let dq = |a: &Joints<f64>, b: &Joints<f64>| {
                    Vector3::new(
                        angle_diff(a.qs1, b.qs1),
                        angle_diff(a.qs2, b.qs2),
                        a.qs3 - b.qs3,
                    ) / (2.0 * h)
                };
                let v_err = rel_err(&dq(&plus.q, &minus.q), &mid.q_dot.to_vector(), 1e-2);
                prop_assert!(v_err < 1e-6, "{side} {mode:?}: velocity relative error {v_err}");
                let a_fd = (plus.q_dot.to_vector() - minus.q_dot.to_vector()) / (2.0 * h);
                let a_err = rel_err(&a_fd, &mid.q_ddot.to_vector(), 1e-2);
                prop_assert!(a_err < 1e-6, "{side} {mode:?}: acceleration relative error {a_err}");
            }
        }
    }

    #[test]
    fn mirror_symmetry(mo in motion()) {
        // The right module at the mirrored pose, with the mirrored tip, has
        // the left module's joints, rates and accelerations.
        let left = unlimited::<f64>(Side::Left);
        let right = unlimited::<f64>(Side::Right);
        let s = Vector3::new(-1.0, 1.0, 1.0);
        for mode in [AssemblyMode::A, AssemblyMode::B] {
            let state = mo.state(0.0);
            let tip = mo.tip(&left, mode, 0.0);
            let mirrored_tip = TipMotion {
                position: tip.position.component_mul(&s),
                velocity: tip.velocity.component_mul(&s),
                acceleration: tip.acceleration.component_mul(&s),
            };
            let l = left.solve_state(&state, &tip, mode).expect("regular");
            let r = right
                .solve_state(&state.mirrored(), &mirrored_tip, mode)
                .expect("regular");
            for (a, b, scale) in [
                (l.q, r.q, 1.0),
                (l.q_dot, r.q_dot, l.q_dot.to_vector().amax().max(1.0)),
                (l.q_ddot, r.q_ddot, l.q_ddot.to_vector().amax().max(1.0)),
            ] {
                let d = Vector3::new(angle_diff(a.qs1, b.qs1), a.qs2 - b.qs2, a.qs3 - b.qs3);
                prop_assert!(d.amax() < 1e-9 * scale, "{mode:?}: {a:?} vs {b:?}");
            }
        }
    }
}

/// The inverse Jacobian's closed form against nalgebra's general inverse.
#[test]
fn closed_form_inverse_matches_general_inverse() {
    let mut worst = 0.0f64;
    for side in [Side::Left, Side::Right] {
        let m = unlimited::<f64>(side);
        for i in 0..200 {
            let t = f64::from(i);
            let q = Joints::new(
                (t * 0.37).sin() * 3.0,
                (t * 0.11).cos() * 1.3,
                10.0 + 3.0 * t,
            );
            let closed = m.jacobian_inverse(&q).expect("regular");
            let general = m.jacobian(&q).try_inverse().expect("regular");
            worst = worst.max((closed - general).amax() / general.amax());
        }
    }
    assert!(worst < 1e-12, "relative difference {worst}");
}

#[test]
fn continuing_keeps_the_mode_and_unwraps_qs1() {
    let m = unlimited::<f64>(Side::Left);
    let pose = Pose::paper_start();
    // A mode-B configuration with qs1 just past 180 deg.
    let q = Joints::new(181f64.to_radians(), 120f64.to_radians(), 100.0);
    let tip = m.fk(&pose, &q).expect("finite");
    let back = m.ik_continuing(&pose, &tip, &q).expect("reachable");
    assert!((back.qs1 - q.qs1).abs() < 1e-12, "{back:?}");
    assert!((back.qs2 - q.qs2).abs() < 1e-12);
    // Plain IK wraps it to (-180, 180].
    let wrapped = m.ik(&pose, &tip, AssemblyMode::B).expect("reachable");
    assert!((wrapped.qs1.to_degrees() + 179.0).abs() < 1e-9);
}

mod bad_inputs {
    use super::*;

    fn left() -> Instrument<f64> {
        Instrument::paper(Side::Left)
    }

    #[test]
    fn non_finite_pose_or_tip_is_named() {
        let tip = Vector3::from(P0_TIP_LEFT);
        for (k, name) in [
            "pose.x",
            "pose.y",
            "pose.z",
            "pose.psi",
            "pose.theta",
            "pose.phi",
        ]
        .iter()
        .enumerate()
        {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut p = Pose::<f64>::paper_start().to_array();
                p[k] = bad;
                match left().ik(&Pose::from_array(p), &tip, AssemblyMode::A) {
                    Err(Error::NonFinite { what, .. }) => assert_eq!(what, *name),
                    other => panic!("{name} = {bad}: {other:?}"),
                }
            }
        }
        for (k, name) in ["tip.x", "tip.y", "tip.z"].iter().enumerate() {
            let mut t = Vector3::from(P0_TIP_LEFT);
            t[k] = f64::NAN;
            match left().ik(&Pose::paper_start(), &t, AssemblyMode::A) {
                Err(Error::NonFinite { what, .. }) => assert_eq!(what, *name),
                other => panic!("{name}: {other:?}"),
            }
        }
        // Rates: a NaN Euler acceleration is named too.
        let mut state = PlatformState::at_rest(Pose::<f64>::paper_start());
        state.acceleration.psi = f64::NAN;
        let tip = TipMotion::still(Vector3::from(P0_TIP_LEFT));
        assert!(matches!(
            left().solve_state(&state, &tip, AssemblyMode::A),
            Err(Error::NonFinite {
                what: "acceleration.psi",
                ..
            })
        ));
    }

    #[test]
    fn tip_at_the_rcm_is_singular() {
        let pose = Pose::<f64>::paper_start();
        let rcm = pose.rotation() * left().geometry().rcm + pose.position();
        match left().ik(&pose, &rcm, AssemblyMode::A) {
            Err(Error::Singular {
                side: Side::Left,
                margin: InstrumentSingularity::Qs3,
                value,
                threshold,
            }) => {
                assert!(value < 1e-12);
                assert!((threshold - 1e-6).abs() < 1e-18);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn direction_out_of_reach() {
        // v = (1, 0, 0): |v_x| = 1 > cos(10 deg).
        let m = left();
        let alpha = 10f64.to_radians();
        let u = Vector3::new(alpha.cos(), 0.0, -alpha.sin()); // R_Y(alpha) (1, 0, 0)
        let p_local = -u * 100.0;
        match m.ik_local(&p_local, AssemblyMode::A) {
            Err(Error::OutOfReach {
                side: Side::Left,
                sin_qs2,
            }) => assert!((sin_qs2 - 1.0 / 10f64.to_radians().cos()).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn direction_on_the_reach_boundary_is_singular() {
        let m = unlimited::<f64>(Side::Left);
        for qs2 in [90.0f64, -90.0, 90.0 - 1e-5, 90.0 + 1e-5] {
            let q = Joints::from_deg_mm(30.0, qs2, 120.0);
            let p = m.fk_local(&q);
            match m.ik_local(&p, AssemblyMode::A) {
                Err(Error::Singular {
                    margin: InstrumentSingularity::CosQs2,
                    value,
                    ..
                }) => assert!(value < 1e-6, "qs2 = {qs2}: {value}"),
                other => panic!("qs2 = {qs2}: {other:?}"),
            }
        }
        // Just outside the band it solves.
        let q = Joints::from_deg_mm(30.0, 89.9, 120.0);
        let back = m
            .ik_local(&m.fk_local(&q), AssemblyMode::A)
            .expect("regular");
        assert!((back.qs2 - q.qs2).abs() < 1e-9);
    }

    #[test]
    fn joint_beyond_its_limit() {
        let pose = Pose::<f64>::paper_start();
        let m = left();
        for (q, joint) in [
            (Joints::from_deg_mm(130.0, 10.0, 100.0), Joint::Qs1),
            (Joints::from_deg_mm(10.0, -85.0, 100.0), Joint::Qs2),
            (Joints::from_deg_mm(10.0, 10.0, 5.0), Joint::Qs3),
            (Joints::from_deg_mm(10.0, 10.0, 350.0), Joint::Qs3),
        ] {
            let tip = m.fk(&pose, &q).expect("finite");
            match m.ik(&pose, &tip, AssemblyMode::A) {
                Err(Error::JointLimit {
                    side: Side::Left,
                    joint: j,
                    value,
                    min,
                    max,
                }) => {
                    assert_eq!(j, joint);
                    assert!(value < min || value > max);
                }
                other => panic!("{joint}: {other:?}"),
            }
        }
    }

    #[test]
    fn invalid_geometry_is_refused() {
        let mut g = InstrumentGeometry::<f64>::paper(Side::Right);
        g.beta = 95f64.to_radians();
        assert!(matches!(
            Instrument::new(g),
            Err(Error::InvalidParameter {
                what: "instrument.beta",
                ..
            })
        ));
        let mut g = InstrumentGeometry::<f64>::paper(Side::Right);
        g.limits.qs3.min = 500.0;
        assert!(matches!(
            Instrument::new(g),
            Err(Error::InvalidParameter { .. })
        ));
    }
}

/// The deprecated name still names the same type, with the same text.
#[test]
#[allow(deprecated)]
fn the_old_name_of_instrument_singularity_is_an_alias() {
    let old: parasils_kin::Margin = InstrumentSingularity::CosQs2;
    assert_eq!(old, InstrumentSingularity::CosQs2);
    assert_eq!(parasils_kin::Margin::Qs3.to_string(), "qs3 (mm)");
}
