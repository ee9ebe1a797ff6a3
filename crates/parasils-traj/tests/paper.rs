//! The paper's reorientation profiles: `psi` 15 deg, `theta` 25 deg,
//! `omega_max = 10 deg/s`, `epsilon_max = 5 deg/s^2` (`docs/model.md`,
//! *Trajectories* and *Check values*), in degrees, in radians, in f64 and in
//! f32.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact times are what these tests check"
)]

use parasils_traj::{
    DoubleS, Error, JerkLimits, Limits, Motion, Multi, Synchronization, Trapezoid,
};

const DEG: f64 = core::f64::consts::PI / 180.0;

#[test]
fn psi_15_deg_is_triangular_3_4641016_s() -> Result<(), Error> {
    let psi = Trapezoid::new(0.0_f64, 15.0, Limits::new(10.0, 5.0))?;
    assert!(psi.is_triangular());
    assert!((psi.duration() - 3.464_101_615_137_754_6).abs() < 1e-12);
    assert!((psi.duration() - 2.0 * (15.0_f64 / 5.0).sqrt()).abs() < 1e-12);
    assert!(psi.peak_velocity() < 10.0);
    let psi32 = Trapezoid::new(0.0_f32, 15.0, Limits::new(10.0, 5.0))?;
    assert!((psi32.duration() - 3.464_101_6).abs() < 1e-6);
    Ok(())
}

#[test]
fn theta_25_deg_is_trapezoidal_4_5_s() -> Result<(), Error> {
    let theta = Trapezoid::new(0.0_f64, 25.0, Limits::new(10.0, 5.0))?;
    assert!(!theta.is_triangular());
    assert_eq!(theta.duration(), 4.5);
    assert_eq!(
        (theta.t_accel(), theta.t_cruise(), theta.t_decel()),
        (2.0, 0.5, 2.0)
    );
    let theta32 = Trapezoid::new(0.0_f32, 25.0, Limits::new(10.0, 5.0))?;
    assert_eq!(theta32.duration(), 4.5);
    Ok(())
}

#[test]
fn phase_synchronised_in_radians_takes_4_5_s_and_psi_stays_below_its_limits() -> Result<(), Error> {
    let lim = Limits::paper();
    let start = [-15.0 * DEG, 10.0 * DEG];
    let goal = [0.0, 35.0 * DEG];
    let m = Multi::new(start, goal, [lim; 2], Synchronization::default())?;
    assert_eq!(m.synchronization(), Synchronization::Phase);
    assert!((m.duration() - 4.5).abs() < 1e-12, "{}", m.duration());
    assert_eq!(m.lead(), Some(1));
    let [psi, theta] = m.axes();
    // psi: a copy of theta scaled by 15/25: 6 deg/s and 3 deg/s^2.
    assert!((psi.peak_velocity() / DEG - 6.0).abs() < 1e-9);
    assert!((psi.peak_acceleration() / DEG - 3.0).abs() < 1e-9);
    assert!(psi.peak_velocity() < lim.v_max && psi.peak_acceleration() < lim.a_max);
    assert_eq!(psi.t_accel(), theta.t_accel());
    // On the straight line: psi's progress is 15/25 of theta's, at every ms.
    for k in 0..=4500 {
        let t = f64::from(k) / 1000.0;
        let [p, q] = m.sample(t);
        let (sp, sq) = (
            (p.position - start[0]) / (15.0 * DEG),
            (q.position - start[1]) / (25.0 * DEG),
        );
        assert!((sp - sq).abs() < 1e-14, "t = {t}: {sp} vs {sq}");
        assert!(p.velocity.abs() <= lim.v_max && p.acceleration.abs() <= lim.a_max);
    }
    Ok(())
}

#[test]
fn phase_synchronised_in_f32_degrees() -> Result<(), Error> {
    let m = Multi::new(
        [0.0_f32, 0.0],
        [15.0, 25.0],
        [Limits::new(10.0, 5.0); 2],
        Synchronization::Phase,
    )?;
    assert_eq!(m.duration(), 4.5);
    assert!(m.axes()[0].peak_velocity() < 10.0 && m.axes()[0].peak_acceleration() < 5.0);
    assert_eq!(m.sampler(1000.0)?.len(), 4501);
    Ok(())
}

#[test]
fn sampling_at_1_khz_gives_4501_samples_ending_on_the_goal() -> Result<(), Error> {
    let goal = [0.0, 35.0 * DEG];
    let m = Multi::new(
        [-15.0 * DEG, 10.0 * DEG],
        goal,
        [Limits::paper(); 2],
        Synchronization::Phase,
    )?;
    let samples = m.sampler(1000.0)?;
    assert_eq!(samples.len(), 4501);
    let mut last = None;
    for s in samples {
        assert_eq!(s.time, s.index as f64 / 1000.0);
        last = Some(s);
    }
    let last = last.ok_or(Error::InvalidRate { value: 0.0 })?;
    assert_eq!((last.index, last.time), (4500, 4.5));
    assert_eq!(last.state.map(|s| s.position), goal);
    assert_eq!(
        last.state.map(|s| (s.velocity, s.acceleration)),
        [(0.0, 0.0); 2]
    );
    Ok(())
}

#[test]
fn time_synchronised_psi_lowers_its_velocity() -> Result<(), Error> {
    let m = Multi::new(
        [0.0_f64, 0.0],
        [15.0, 25.0],
        [Limits::new(10.0, 5.0); 2],
        Synchronization::Time,
    )?;
    let [psi, _] = m.axes();
    assert_eq!(psi.duration(), 4.5);
    assert_eq!(psi.peak_acceleration(), 5.0);
    // v = 2 d / (T + sqrt(T^2 - 4 d / a)) = 30 / (4.5 + sqrt(8.25)).
    assert!((psi.peak_velocity() - 30.0 / (4.5 + 8.25_f64.sqrt())).abs() < 1e-12);
    Ok(())
}

#[test]
fn none_synchronised_axes_keep_their_own_times() -> Result<(), Error> {
    let m = Multi::new(
        [0.0_f64, 0.0],
        [15.0, 25.0],
        [Limits::new(10.0, 5.0); 2],
        Synchronization::None,
    )?;
    let [psi, theta] = m.axes();
    assert!((psi.duration() - 2.0 * 3.0_f64.sqrt()).abs() < 1e-12);
    assert_eq!(theta.duration(), 4.5);
    assert_eq!(m.duration(), 4.5);
    Ok(())
}

#[test]
fn absolute_reading_takes_5_s() -> Result<(), Error> {
    // `docs/model.md`, *Check values*, `--absolute`: psi -15 -> 15, theta 10 -> 25.
    let m = Multi::new(
        [-15.0_f64, 10.0],
        [15.0, 25.0],
        [Limits::new(10.0, 5.0); 2],
        Synchronization::Phase,
    )?;
    assert!((m.duration() - 5.0).abs() < 1e-12);
    Ok(())
}

#[test]
fn jerk_limited_is_never_shorter_on_the_paper_axes() -> Result<(), Error> {
    for d in [15.0_f64, 25.0] {
        let trap = Trapezoid::new(0.0, d, Limits::new(10.0, 5.0))?;
        for j in [1.0, 5.0, 20.0, 1e3] {
            let ds = DoubleS::new(0.0, d, JerkLimits::new(10.0, 5.0, j))?;
            assert!(ds.duration() >= trap.duration(), "d={d} j={j}");
            assert!(
                ds.peak_velocity() <= 10.0 && ds.peak_acceleration() <= 5.0 && ds.peak_jerk() <= j
            );
        }
    }
    Ok(())
}
