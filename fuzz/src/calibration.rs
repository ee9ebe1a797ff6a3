//! The calibration's inputs: the measurement reader
//! (`parasils_calib::data::read_csv`, what `parasils calibrate` reads) and
//! the tolerance specification parser (`parasils_tolerance::Spec`, what
//! `parasils tolerance --spec` reads), with arbitrary bytes. No call may
//! panic; an error has a message; what is accepted is finite and comes back
//! unchanged through the project's own writer.
//!
//! The fit itself (Levenberg-Marquardt over 51 parameters, milliseconds per
//! data set) is not run here: its property tests cover it, and a target
//! that slow could not reach the campaign's executions.

use parasils_calib::data::{self, Sigma};
use parasils_tolerance::{Perturbation, Spec};

/// The `calibration_data` target: the first byte picks the default standard
/// deviations the reader gives rows without their own (none, or some), the
/// rest is the CSV text.
pub fn calibration_data(data: &[u8]) {
    let (default_sigma, text) = match data.split_first() {
        Some((&b, rest)) if b & 1 == 1 => (
            Sigma {
                q_mm: 0.01,
                position_mm: 0.02,
                angle_deg: 0.005,
            },
            rest,
        ),
        Some((_, rest)) => (Sigma::default(), rest),
        None => (Sigma::default(), data),
    };
    let rows = match data::read_csv(text, "measurements", default_sigma) {
        Ok(rows) => rows,
        Err(e) => {
            assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
            return;
        }
    };
    if let Err(e) = data::check(&rows) {
        panic!("the reader accepted a row its check refuses: {e}");
    }
    // Back through the writer: the numbers to the last bit (a standard
    // deviation of -0 may come back as 0, the same value).
    let written = data::to_csv_string(&rows);
    let back = data::read_csv(written.as_bytes(), "written", Sigma::default())
        .unwrap_or_else(|e| panic!("the written measurements are refused: {e}\n{written}"));
    assert_eq!(back.len(), rows.len(), "{written}");
    for (a, b) in rows.iter().zip(&back) {
        let bits = |m: &data::Measurement| {
            m.q_mm
                .iter()
                .chain(&m.pose)
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(
            bits(a),
            bits(b),
            "a number changed through the writer:\n{written}"
        );
        assert_eq!(a.sigma, b.sigma, "a standard deviation changed:\n{written}");
    }
}

/// The `tolerance_spec` target: the first byte picks TOML (even) or JSON
/// (odd), the rest is the text.
pub fn tolerance_spec(data: &[u8]) {
    let (json, rest) = match data.split_first() {
        Some((&b, rest)) => (b & 1 == 1, rest),
        None => (false, data),
    };
    let text = String::from_utf8_lossy(rest);
    let parsed = if json {
        Spec::from_json(&text)
    } else {
        Spec::from_toml(&text)
    };
    let spec = match parsed {
        Ok(spec) => spec,
        Err(e) => {
            assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
            return;
        }
    };
    let mut widest: f64 = 0.0;
    for (family, d) in spec.iter() {
        let (sd, extreme) = (d.std_dev(), d.extreme());
        assert!(
            sd.is_finite() && sd >= 0.0 && extreme.is_finite() && extreme >= 0.0,
            "{family:?}: an accepted distribution {d:?} with standard deviation {sd}, extreme {extreme}"
        );
        widest = widest.max(extreme);
    }
    let written = spec.to_toml();
    let back = Spec::from_toml(&written)
        .unwrap_or_else(|e| panic!("the written specification is refused: {e}\n{written}"));
    assert_eq!(
        back, spec,
        "the specification changed through its own TOML:\n{written}"
    );
    // A draw is finite wherever its widths leave room for the variates
    // (a normal variate stays within 40 standard deviations).
    if widest < f64::MAX / 64.0 {
        let seed = u64::from(rest.first().copied().unwrap_or(0));
        let p = Perturbation::draw(&spec, seed, rest.len() as u64);
        assert!(
            p.coordinates().iter().all(|c| c.is_finite()),
            "a draw of {spec:?} is not finite"
        );
    }
}
