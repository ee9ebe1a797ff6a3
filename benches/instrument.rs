//! One spherical instrument module's inverse kinematics, closed form
//! (`parasils_kin::Instrument::ik`), in `f64` and `f32`, against a general
//! numeric IK on the same chain: the `k` crate's Jacobian solver
//! (`k::JacobianIkSolver`, Newton steps on the tip position).
//!
//! Before the timings, the bench prints the accuracy each solver reaches over
//! the paper's motion (the tip recomputed from the joints by the same forward
//! kinematics, `Instrument::tip`, against the target) and a side-by-side
//! timing of the two in this run, so that the ratio is measured on one
//! machine state.
//!
//! `cargo bench -p parasils --bench instrument`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;
use std::time::Instant;

use criterion::Criterion;
use k::nalgebra as kna;
use k::prelude::*;
use nalgebra::Vector3;
use parasils::Real;
use parasils::kin::{AssemblyMode, Instrument, Joints, Pose, Side, TipTargets};

use common::paper_motion;

/// The left module of the paper as a `k` serial chain rooted at the module's
/// RCM frame at `pose`:
/// `M_L = R_Y(alpha) R_X(qs1) R_Y(qs2) R_X(beta) T_Z(-qs3)` (see
/// `docs/model.md`, *Instrument modules*).
struct KArm {
    root: k::Node<f64>,
    arm: k::SerialChain<f64>,
}

impl KArm {
    fn paper() -> Self {
        let m = Instrument::<f64>::paper(Side::Left);
        let g = m.geometry();
        let root = k::NodeBuilder::<f64>::new().name("rcm").into_node();
        let qs1 = k::NodeBuilder::new()
            .name("qs1")
            .rotation(kna::UnitQuaternion::from_axis_angle(
                &kna::Vector3::y_axis(),
                g.alpha,
            ))
            .joint_type(k::JointType::Rotational {
                axis: kna::Vector3::x_axis(),
            })
            .into_node();
        let qs2 = k::NodeBuilder::new()
            .name("qs2")
            .joint_type(k::JointType::Rotational {
                axis: kna::Vector3::y_axis(),
            })
            .into_node();
        let qs3 = k::NodeBuilder::new()
            .name("qs3")
            .rotation(kna::UnitQuaternion::from_axis_angle(
                &kna::Vector3::x_axis(),
                g.beta,
            ))
            .joint_type(k::JointType::Linear {
                axis: -kna::Vector3::z_axis(),
            })
            .into_node();
        qs1.set_parent(&root);
        qs2.set_parent(&qs1);
        qs3.set_parent(&qs2);
        let arm = k::SerialChain::from_end(&qs3);
        Self { root, arm }
    }

    /// Puts the chain's root on the left RCM at `pose`.
    fn place(&self, pose: &Pose<f64>) {
        let r = pose.rotation();
        let rcm = Instrument::<f64>::paper(Side::Left).geometry().rcm;
        let o = pose.position() + r * rcm;
        let m = kna::Matrix3::from_iterator(r.iter().copied());
        let rot =
            kna::UnitQuaternion::from_rotation_matrix(&kna::Rotation3::from_matrix_unchecked(m));
        self.root.set_origin(kna::Isometry3::from_parts(
            kna::Translation3::new(o.x, o.y, o.z),
            rot,
        ));
        self.arm.update_transforms();
    }

    fn set(&self, q: &Joints<f64>) {
        self.arm
            .set_joint_positions(&[q.qs1, q.qs2, q.qs3])
            .expect("no limits");
    }

    fn joints(&self) -> Joints<f64> {
        let q = self.arm.joint_positions();
        Joints::new(q[0], q[1], q[2])
    }

    /// The numeric IK of `tip` (mm, fixed frame) from the joints set.
    fn solve(&self, solver: &k::JacobianIkSolver<f64>, tip: &Vector3<f64>) -> bool {
        let target = kna::Isometry3::translation(tip.x, tip.y, tip.z);
        let position_only = k::Constraints {
            rotation_x: false,
            rotation_y: false,
            rotation_z: false,
            ..k::Constraints::default()
        };
        solver
            .solve_with_constraints(&self.arm, &target, &position_only)
            .is_ok()
    }
}

/// `k`'s solver as shipped (`JacobianIkSolver::default()`: half Newton
/// steps, 1e-3 position tolerance, here mm, 10 tries).
fn k_default() -> k::JacobianIkSolver<f64> {
    k::JacobianIkSolver::default()
}

/// `k`'s solver at its best for this comparison: full Newton steps (the
/// multiplier 1), the given position tolerance (mm), 50 tries.
fn k_with_tolerance(mm: f64) -> k::JacobianIkSolver<f64> {
    k::JacobianIkSolver::new(mm, 1.0, 1.0, 50)
}

/// `k` at the closed form's accuracy: full Newton steps and a 1e-13 mm
/// tolerance (about the rounding of the 620 mm coordinates), at which it
/// still converges on every pose of the paper's motion (the report prints
/// the accuracy reached at each tolerance).
fn k_tuned() -> k::JacobianIkSolver<f64> {
    k_with_tolerance(1e-13)
}

/// Tip errors (mm) over the paper's motion every 10 ms, each solver started
/// (for `k`) from its own solution 10 ms earlier: `(max, median)`.
fn accuracy(solver: Option<&k::JacobianIkSolver<f64>>) -> (f64, f64, usize) {
    let motion = paper_motion::<f64>();
    let left = Instrument::<f64>::paper(Side::Left);
    let tip = TipTargets::<f64>::paper().left;
    let karm = KArm::paper();
    let mut errors = Vec::new();
    let mut failures = 0;
    let p0 = Pose::paper_start();
    let mut q = left.ik(&p0, &tip, AssemblyMode::A).expect("regular at P0");
    for k in 0..=450 {
        let pose = motion.state_at(f64::from(k) / 100.0).pose;
        q = match solver {
            None => left.ik(&pose, &tip, AssemblyMode::A).expect("regular"),
            Some(s) => {
                karm.place(&pose);
                karm.set(&q);
                if !karm.solve(s, &tip) {
                    failures += 1;
                }
                karm.joints()
            }
        };
        errors.push((left.fk(&pose, &q).expect("finite") - tip).norm());
    }
    errors.sort_by(f64::total_cmp);
    (errors[errors.len() - 1], errors[errors.len() / 2], failures)
}

/// Median time (ns) per call of `f` over `blocks` blocks of `n` calls.
fn median_ns(blocks: usize, n: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..blocks)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..n {
                f();
            }
            t.elapsed().as_nanos() as f64 / n as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[blocks / 2]
}

/// The accuracies and the ratio, printed before the criterion benches.
fn report() {
    println!("instrument IK accuracy over the paper's motion (tip error, mm, 451 poses):");
    let (max, med, _) = accuracy(None);
    println!("  closed form (parasils)               max {max:.2e}  median {med:.2e}");
    let (left, pose, prev, tip) = ik_inputs();
    let karm = KArm::paper();
    let mut k_times = Vec::new();
    for (name, s) in [
        ("k default (half steps, 1e-3 mm)    ", k_default()),
        (
            "k full steps, 1e-11 mm             ",
            k_with_tolerance(1e-11),
        ),
        (
            "k full steps, 1e-12 mm             ",
            k_with_tolerance(1e-12),
        ),
        (
            "k full steps, 2e-13 mm             ",
            k_with_tolerance(2e-13),
        ),
        (
            "k full steps, 1e-13 mm             ",
            k_with_tolerance(1e-13),
        ),
    ] {
        let (max, med, fail) = accuracy(Some(&s));
        karm.place(&pose);
        let t = median_of_medians(|| {
            median_ns(21, 200, || {
                karm.set(&prev);
                black_box(karm.solve(&s, black_box(&tip)));
            })
        });
        println!(
            "  {name}  max {max:.2e}  median {med:.2e}  not converged: {fail}/451, {t:.0} ns warm"
        );
        k_times.push(t);
    }

    // Side by side: the closed form from the Euler angles (`ik`) and from the
    // tip in the module's frame (`ik_local`, the platform frame shared, as
    // in the controller and as k's chain, whose root is placed once), and
    // k from the previous cycle's joints.
    let local = left.tip_to_local(&pose, &tip).expect("finite");
    let from_pose = median_of_medians(|| {
        median_ns(21, 20_000, || {
            let _ = black_box(left.ik(black_box(&pose), black_box(&tip), AssemblyMode::A));
        })
    });
    let from_frame = median_of_medians(|| {
        median_ns(21, 20_000, || {
            let _ = black_box(left.ik_local(black_box(&local), AssemblyMode::A));
        })
    });
    println!(
        "side by side, this run (median ns per IK; k warm-started from the joints 1 ms earlier):"
    );
    println!(
        "  closed form from the Euler angles {from_pose:.1} ns, from the module frame {from_frame:.1} ns"
    );
    for (name, t) in [
        "k default",
        "k 1e-11 mm",
        "k 1e-12 mm",
        "k 2e-13 mm",
        "k 1e-13 mm",
    ]
    .iter()
    .zip(&k_times)
    {
        println!(
            "  {name}: {t:.0} ns = {:.0}x the closed form from the angles, {:.0}x from the frame",
            t / from_pose,
            t / from_frame
        );
    }
}

/// The median of 5 medians.
fn median_of_medians(mut f: impl FnMut() -> f64) -> f64 {
    let mut v: Vec<f64> = (0..5).map(|_| f()).collect();
    v.sort_by(f64::total_cmp);
    v[2]
}

/// The left module, the pose at `t = 1 s`, the joints 1 ms earlier, the tip.
fn ik_inputs() -> (Instrument<f64>, Pose<f64>, Joints<f64>, Vector3<f64>) {
    let motion = paper_motion::<f64>();
    let left = Instrument::paper(Side::Left);
    let tip = TipTargets::paper().left;
    let pose = motion.state_at(1.0).pose;
    let before = motion.state_at(0.999).pose;
    let prev = left.ik(&before, &tip, AssemblyMode::A).expect("regular");
    (left, pose, prev, tip)
}

fn bench_closed_form<T: Real>(c: &mut Criterion, name: &str) {
    let motion = paper_motion::<T>();
    let left = Instrument::<T>::paper(Side::Left);
    let tip = TipTargets::<T>::paper().left;
    let pose = motion.state_at(T::lit(1.0)).pose;
    c.bench_function(&format!("instrument/ik/{name}"), |b| {
        b.iter(|| left.ik(black_box(&pose), black_box(&tip), AssemblyMode::A))
    });
    let local = left.tip_to_local(&pose, &tip).expect("finite");
    c.bench_function(&format!("instrument/ik_local/{name}"), |b| {
        b.iter(|| left.ik_local(black_box(&local), AssemblyMode::A))
    });
}

fn bench_k(c: &mut Criterion) {
    let (_, pose, prev, tip) = ik_inputs();
    let karm = KArm::paper();
    karm.place(&pose);
    for (name, solver) in [("tuned", k_tuned()), ("default", k_default())] {
        c.bench_function(&format!("instrument/k_jacobian_{name}/warm/f64"), |b| {
            b.iter(|| {
                karm.set(&prev);
                karm.solve(&solver, black_box(&tip))
            })
        });
    }
    // From the start pose's joints to the end of the motion (psi +15, theta +25 deg).
    let motion = paper_motion::<f64>();
    let end = motion.state_at(4.5).pose;
    let left = Instrument::<f64>::paper(Side::Left);
    let start_q = left
        .ik(&Pose::paper_start(), &tip, AssemblyMode::A)
        .expect("regular");
    karm.place(&end);
    let solver = k_tuned();
    c.bench_function("instrument/k_jacobian_tuned/cold/f64", |b| {
        b.iter(|| {
            karm.set(&start_q);
            karm.solve(&solver, black_box(&tip))
        })
    });
}

fn main() {
    // Not when criterion is only asked to list or test the benchmarks.
    if !std::env::args().any(|a| a == "--list" || a == "--test") {
        report();
    }
    let mut c = common::criterion();
    bench_closed_form::<f64>(&mut c, "f64");
    bench_closed_form::<f32>(&mut c, "f32");
    bench_k(&mut c);
    c.final_summary();
}
