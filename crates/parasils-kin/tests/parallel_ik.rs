//! Module 1's inverse kinematics against independent truths: the check
//! values of `docs/model.md` (*Check values*: the symmetric pose in closed
//! form, `P0`), the geometry (normalised guides, the symmetric layout), and
//! every error path of the IK (a leg out of reach, a stroke, non-finite
//! input, invalid geometries).

use nalgebra::Vector3;
use parasils_kin::error::Error;
use parasils_kin::instrument::Interval;
use parasils_kin::parallel::SymmetricLayout;
use parasils_kin::{ParallelGeometry, ParallelRobot, PlatformFrame, PlatformState, Pose, Real};

mod common;
use common::module1::{Q_P0, Q_SYMMETRIC, symmetric_pose, to_f64};

fn check<T: Real>(tol: f64) {
    let robot = ParallelRobot::<T>::assumed();
    let q = to_f64(&robot.ik(&symmetric_pose()).expect("reachable"));
    for (j, qj) in q.iter().enumerate() {
        assert!(
            (qj - Q_SYMMETRIC).abs() < tol,
            "symmetric pose: q{} = {qj}",
            j + 1
        );
    }
    let q = to_f64(&robot.ik(&Pose::paper_start()).expect("reachable"));
    for j in 0..6 {
        assert!(
            (q[j] - Q_P0[j]).abs() < tol,
            "P0: q{} = {}, expected {}",
            j + 1,
            q[j],
            Q_P0[j]
        );
    }
}

#[test]
fn symmetric_pose_and_p0_in_f64() {
    // The table prints three decimals.
    check::<f64>(5e-4);
}

#[test]
fn symmetric_pose_and_p0_in_f32() {
    check::<f32>(6e-4);
}

#[test]
fn symmetric_pose_is_exactly_symmetric() {
    let q = ParallelRobot::<f64>::assumed()
        .ik(&symmetric_pose())
        .expect("reachable");
    // 400 - sqrt(94400), from |r|^2 = 188100 and l^2 = 122500.
    let exact = 400.0 - 94_400f64.sqrt();
    for qj in q.0 {
        assert!((qj - exact).abs() < 1e-12, "{qj} vs {exact}");
    }
}

#[test]
fn guide_directions_are_normalised() {
    let mut g = ParallelGeometry::<f64>::assumed();
    for guide in g.guides.iter_mut() {
        guide.direction *= 2.5;
    }
    let robot = ParallelRobot::new(g).expect("valid");
    assert!((robot.geometry().guides[3].direction.norm() - 1.0).abs() < 1e-15);
    let q = robot.ik(&Pose::paper_start()).expect("reachable");
    let q0 = ParallelRobot::<f64>::assumed()
        .ik(&Pose::paper_start())
        .expect("reachable");
    assert!((0..6).all(|j| (q[j] - q0[j]).abs() < 1e-12));
}

#[test]
fn layout_builds_the_assumed_geometry() {
    let g = ParallelGeometry::<f64>::from_layout(&SymmetricLayout::assumed());
    assert!(!g.assumed);
    let a = ParallelGeometry::<f64>::assumed();
    for j in 0..6 {
        let (x, y) = (&g.guides[j], &a.guides[j]);
        assert!((x.point - y.point).norm() < 1e-12, "guide {j}");
        assert_eq!(
            (x.direction, x.link_length, x.branch, x.stroke),
            (y.direction, y.link_length, y.branch, y.stroke)
        );
    }
    for i in 0..3 {
        assert!((g.nodes[i] - a.nodes[i]).norm() < 1e-12, "node {i}");
    }
}

#[test]
fn pose_out_of_reach_names_the_actuator() {
    let robot = ParallelRobot::<f64>::assumed();
    // Sideways by 450 mm towards -Y: leg 1's node (at Y = 150 mm in the
    // symmetric pose) is 386 mm from the lines of its guides (at Y = 200).
    let pose = Pose::from_mm_deg(0.0, -450.0, -500.0, 0.0, 0.0, -60.0);
    let e = robot.ik(&pose).expect_err("out of reach");
    match e {
        Error::LegOutOfReach {
            actuator: 1,
            discriminant,
        } => {
            // l^2 - |r_perp|^2 with r_perp = (-160, -500) mm.
            let expected = 350f64.powi(2) - 160f64.powi(2) - 500f64.powi(2);
            assert!((discriminant - expected).abs() < 1e-6, "{discriminant}");
        }
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("actuator q1"), "{e}");
    // Towards +X: leg 1's node is 661 mm from q2's guide line (at X = -160 mm).
    let e = robot
        .ik(&Pose::from_mm_deg(500.0, 0.0, -500.0, 0.0, 0.0, -60.0))
        .expect_err("out of reach");
    assert!(
        matches!(e, Error::LegOutOfReach { actuator: 2, .. }),
        "{e:?}"
    );
    // margins(), solve() and the rates fail the same way, not with NaN.
    assert!(robot.margins(&pose).is_err());
    let frame = PlatformState::at_rest(pose).frame().expect("finite");
    assert!(matches!(
        robot.solve(&frame),
        Err(Error::LegOutOfReach { actuator: 1, .. })
    ));
}

#[test]
fn actuator_beyond_its_stroke() {
    let robot = ParallelRobot::<f64>::assumed();
    // Raised by 100 mm from the symmetric pose: q = 300 - sqrt(94400) < 0.
    let pose = Pose::from_mm_deg(0.0, 0.0, -400.0, 0.0, 0.0, -60.0);
    let e = robot.ik(&pose).expect_err("beyond the stroke");
    match e {
        Error::ActuatorLimit {
            actuator: 1,
            value,
            min,
            max,
        } => {
            assert!((value - (300.0 - 94_400f64.sqrt())).abs() < 1e-9);
            assert!(min.abs() < 1e-15 && (max - 320.0).abs() < 1e-12);
        }
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("q1 = -7.24583 mm"), "{e}");
    // solve() checks the strokes too; ik_unchecked() does not.
    let frame = PlatformState::at_rest(pose).frame().expect("finite");
    assert!(matches!(
        robot.solve(&frame),
        Err(Error::ActuatorLimit { actuator: 1, .. })
    ));
    assert!(robot.ik_unchecked(&pose).expect("in reach")[0] < 0.0);
    // The margin to the stroke is reported, negative.
    assert!(robot.margins(&pose).expect("in reach").stroke[0] < -7.0);
}

#[test]
fn non_finite_values_are_named() {
    let robot = ParallelRobot::<f64>::assumed();
    let mut pose = Pose::paper_start();
    pose.theta = f64::NAN;
    assert!(matches!(
        robot.ik(&pose),
        Err(Error::NonFinite {
            what: "pose.theta",
            ..
        })
    ));
    let q = robot.ik(&Pose::paper_start()).expect("reachable");
    let mut bad_q = q;
    bad_q.0[4] = f64::INFINITY;
    assert!(matches!(
        robot.fk(&bad_q, &Pose::paper_start()),
        Err(Error::NonFinite { what: "q5", .. })
    ));
    assert!(matches!(
        robot.fk(&q, &pose),
        Err(Error::NonFinite {
            what: "pose.theta",
            ..
        })
    ));
    let mut st = PlatformState::at_rest(Pose::paper_start());
    st.velocity.x = f64::NAN;
    assert!(matches!(
        robot.solve_state(&st),
        Err(Error::NonFinite {
            what: "velocity.x",
            ..
        })
    ));
    let frame = PlatformFrame::new(&PlatformState::at_rest(Pose::paper_start()));
    assert!(matches!(
        robot.rates(&frame, &bad_q),
        Err(Error::NonFinite { what: "q5", .. })
    ));
    assert!(robot.residual(&pose, &q).is_err());
    // A frame built without the check is refused, not turned into NaN.
    let mut st = PlatformState::at_rest(Pose::paper_start());
    st.acceleration.psi = f64::NAN;
    let unchecked = PlatformFrame::new(&st);
    assert!(matches!(
        robot.solve(&unchecked),
        Err(Error::NonFinite { what: "frame", .. })
    ));
    assert!(matches!(
        robot.rates(&unchecked, &q),
        Err(Error::NonFinite { what: "frame", .. })
    ));
}

#[test]
fn invalid_geometries_are_named() {
    type Spoil = fn(&mut ParallelGeometry<f64>);
    let cases: [(Spoil, &str); 8] = [
        (
            |g| g.guides[2].direction = Vector3::zeros(),
            "module1.guides[2].direction",
        ),
        (
            |g| g.guides[5].link_length = -1.0,
            "module1.guides[5].link_length",
        ),
        (
            |g| g.guides[0].stroke = Interval::new(10.0, 0.0),
            "module1.guides[0].stroke",
        ),
        (
            |g| g.guides[1].point.y = f64::NAN,
            "module1.guides[1].point.y",
        ),
        (|g| g.nodes[2].z = f64::INFINITY, "module1.nodes[2].z"),
        (|g| g.nodes = [Vector3::zeros(); 3], "module1.nodes"),
        (|g| g.thresholds.serial = 0.0, "module1.thresholds.serial"),
        (|g| g.fk.max_iterations = 0, "module1.fk.max_iterations"),
    ];
    for (spoil, name) in cases {
        let mut g = ParallelGeometry::assumed();
        spoil(&mut g);
        match ParallelRobot::new(g) {
            Err(Error::InvalidParameter { what, .. } | Error::NonFinite { what, .. }) => {
                assert_eq!(what, name);
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}
