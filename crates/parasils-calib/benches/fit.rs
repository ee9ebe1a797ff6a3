//! One calibration of 50 planned poses of a perturbed robot (module 1's
//! assumed geometry, every parameter moved up to 2 mm or 1 deg), with the
//! noise of the tests: the target is under 50 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use parasils_calib::plan::{PlanOptions, plan};
use parasils_calib::{FitOptions, Measurement, ParameterMap, Sigma, calibrate};
use parasils_io::Rng;
use parasils_kin::{ParallelGeometry, ParallelRobot, Pose};

fn data() -> (ParallelGeometry<f64>, Vec<Measurement>) {
    let nominal = ParallelGeometry::<f64>::assumed();
    let map = ParameterMap::new(&nominal).expect("valid");
    let mut rng = Rng::new(3);
    let mut x = map.nominal_vector();
    let scales = map.scales();
    for (k, v) in x.iter_mut().enumerate() {
        // 2 mm on the lengths, 1 deg (tan) on the directions.
        let bound = if scales[k] < 1.0 {
            1f64.to_radians().tan()
        } else {
            2.0
        };
        *v += rng.uniform(-bound, bound);
    }
    let truth = ParallelRobot::new(map.geometry(&x)).expect("valid");
    let options = PlanOptions {
        poses: 50,
        candidates: 600,
        ..Default::default()
    };
    let poses = plan(&nominal, &options).expect("plan").poses;
    let sigma = Sigma {
        q_mm: 0.01,
        position_mm: 0.02,
        angle_deg: 0.01,
    };
    let data = poses
        .iter()
        .map(|p| {
            let q = truth
                .ik_unchecked(&Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]))
                .expect("in reach");
            let noisy: [f64; 6] = core::array::from_fn(|j| q[j] + 0.01 * rng.normal());
            let pose: [f64; 6] =
                core::array::from_fn(|k| p[k] + if k < 3 { 0.02 } else { 0.01 } * rng.normal());
            Measurement {
                q_mm: noisy,
                pose,
                sigma,
            }
        })
        .collect();
    (nominal, data)
}

fn bench(c: &mut Criterion) {
    let (nominal, data) = data();
    let options = FitOptions::default();
    c.bench_function("calibrate 50 poses (weighted, two passes)", |b| {
        b.iter(|| calibrate(&nominal, &data, &options).expect("fit"));
    });
    let unweighted: Vec<Measurement> = data
        .iter()
        .map(|m| Measurement {
            sigma: Sigma::default(),
            ..*m
        })
        .collect();
    c.bench_function("calibrate 50 poses (unweighted)", |b| {
        b.iter(|| calibrate(&nominal, &unweighted, &options).expect("fit"));
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
