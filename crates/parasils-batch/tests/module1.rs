//! Module 1's IK in lanes against the scalar `ParallelRobot::ik`, on every
//! level this CPU supports: the same outcome row by row (the sliders to the
//! bit, or the same typed error), over random poses in and out of reach and
//! past the strokes, and non-finite ones.

use parasils_batch::{BatchError, Level, Module1Ik, OnRowError, Strided};
use parasils_kin::{ParallelRobot, Pose};
use proptest::prelude::*;

fn check(pose: &[f64]) -> usize {
    let robot = ParallelRobot::<f64>::assumed();
    let n = pose.len() / 6;
    let mut solved = 0;
    for level in Level::supported() {
        let ik = Module1Ik::new(robot).at_level(level).expect("supported");
        let (mut out, mut ok) = (vec![0.0; 6 * n], vec![false; n]);
        ik.solve(
            0..n,
            Strided::rows(pose),
            &mut out,
            &mut ok,
            OnRowError::Nan,
        )
        .expect("NaN rows do not stop");
        let mut first = None;
        solved = 0;
        for i in 0..n {
            let p = Pose::from_array(<[f64; 6]>::try_from(&pose[6 * i..6 * i + 6]).expect("six"));
            match robot.ik(&p) {
                Ok(q) => {
                    assert!(ok[i], "{level} row {i}");
                    for (j, v) in q.to_array().iter().enumerate() {
                        assert_eq!(
                            out[6 * i + j].to_bits(),
                            v.to_bits(),
                            "{level} row {i} q{}",
                            j + 1
                        );
                    }
                    solved += 1;
                }
                Err(e) => {
                    assert!(!ok[i], "{level} row {i}: {e}");
                    assert!(out[6 * i..6 * i + 6].iter().all(|v| v.is_nan()));
                    first.get_or_insert((i, e));
                }
            }
        }
        let (mut out2, mut ok2) = (vec![0.0; 6 * n], vec![false; n]);
        let stopped = ik.solve(
            0..n,
            Strided::rows(pose),
            &mut out2,
            &mut ok2,
            OnRowError::Stop,
        );
        match first {
            Some((row, error)) => {
                assert_eq!(stopped, Err(BatchError::Row { row, error }), "{level}")
            }
            None => assert_eq!(stopped, Ok(()), "{level}"),
        }
    }
    solved
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn module1_ik_is_the_scalar_path(
        rows in prop::collection::vec((prop::array::uniform3(-1.0f64..1.0), prop::array::uniform3(-1.0f64..1.0)), 1..80),
        spread_mm in prop::sample::select(vec![5.0, 40.0, 200.0]),
        spread_rad in prop::sample::select(vec![0.05, 0.4, 3.0]),
    ) {
        let p0 = Pose::<f64>::paper_start().to_array();
        let mut pose = Vec::new();
        for (dp, da) in &rows {
            pose.extend((0..3).map(|j| p0[j] + dp[j] * spread_mm));
            pose.extend((0..3).map(|j| p0[3 + j] + da[j] * spread_rad));
        }
        check(&pose);
    }
}

#[test]
fn module1_ik_edges() {
    let names: Vec<&str> = Level::supported().map(Level::name).collect();
    eprintln!("module 1 IK: levels run: {}", names.join(", "));
    let p0 = Pose::<f64>::paper_start().to_array();
    let mut pose = Vec::new();
    for k in 0..64 {
        let mut p = p0;
        p[k % 6] += [0.0, 1e3, -1e3, f64::NAN, f64::INFINITY, 1e7][k / 6 % 6]
            * if k % 2 == 0 { 1.0 } else { 0.01 };
        pose.extend(p);
    }
    let solved = check(&pose);
    assert!(
        solved > 0 && solved < 64,
        "both outcomes: {solved} of 64 solved"
    );
    // The paper's start pose is solved in lanes, to the bit.
    assert_eq!(check(&p0), 1);
}
