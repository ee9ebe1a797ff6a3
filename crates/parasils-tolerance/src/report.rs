//! What a designer reads: the percentiles of the deviations, their
//! histogram, the failures, and which tolerance to tighten.

use core::fmt;

use crate::linear::{Linearisation, Sensitivity};
use crate::replay::ReplayFailure;
use crate::spec::Spec;
use crate::study::Results;

/// The percentile levels reported, percent.
pub const LEVELS: [f64; 4] = [50.0, 95.0, 99.0, 99.9];

/// The number of histogram bins.
pub const BINS: usize = 40;

/// The distribution of one column over the samples that did not fail.
#[derive(Debug, Clone, PartialEq)]
pub struct Stats {
    /// `(level, value)` at each of [`LEVELS`], by linear interpolation
    /// between the order statistics (NumPy's default `percentile`).
    pub percentiles: Vec<(f64, f64)>,
    /// The mean.
    pub mean: f64,
    /// The largest value.
    pub max: f64,
}

/// The `p`-th percentile of the sorted `x` (non-empty), NumPy's `linear`.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    let Some(&last) = sorted.last() else {
        return f64::NAN;
    };
    let pos = (sorted.len() - 1) as f64 * p / 100.0;
    let lo = pos.floor() as usize;
    let hi = (lo + 1).min(sorted.len() - 1);
    let (a, b) = (sorted[lo], sorted.get(hi).copied().unwrap_or(last));
    a + (b - a) * (pos - lo as f64)
}

impl Stats {
    /// The statistics of the finite values of `column` (NaN everywhere when
    /// there is none).
    pub fn new(column: impl Iterator<Item = f64>) -> Self {
        let mut v: Vec<f64> = column.filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        let mean = if v.is_empty() {
            f64::NAN
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        };
        Self {
            percentiles: LEVELS.iter().map(|&p| (p, percentile(&v, p))).collect(),
            mean,
            max: v.last().copied().unwrap_or(f64::NAN),
        }
    }
}

/// The histogram of the tip deviations.
#[derive(Debug, Clone, PartialEq)]
pub struct Histogram {
    /// The [`BINS`] + 1 bin edges, mm, from 0 to the largest deviation.
    pub edges_mm: Vec<f64>,
    /// The left tip's counts per bin.
    pub left: Vec<u64>,
    /// The right tip's counts per bin.
    pub right: Vec<u64>,
}

impl Histogram {
    fn new(results: &Results) -> Self {
        let finite = |c: &[f64]| {
            c.iter()
                .copied()
                .filter(|x| x.is_finite())
                .collect::<Vec<_>>()
        };
        let (left, right) = (
            finite(&results.left_tip_dev_mm),
            finite(&results.right_tip_dev_mm),
        );
        let top = left.iter().chain(&right).copied().fold(0.0, f64::max);
        let top = if top > 0.0 { top } else { 1.0 };
        let edges_mm = (0..=BINS).map(|k| top * k as f64 / BINS as f64).collect();
        let count = |v: &[f64]| {
            let mut c = vec![0u64; BINS];
            for &x in v {
                let k = ((x / top * BINS as f64) as usize).min(BINS - 1);
                c[k] += 1;
            }
            c
        };
        Self {
            edges_mm,
            left: count(&left),
            right: count(&right),
        }
    }
}

/// The summary of a study's results.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// The number of samples.
    pub samples: usize,
    /// The number of samples whose robot could not be followed.
    pub failed: usize,
    /// The first failures (at most 5) and why.
    pub first_failures: Vec<(u64, ReplayFailure)>,
    /// The larger of the two tip deviations, per sample, mm.
    pub tip: Stats,
    /// The left tip's deviation, mm.
    pub left: Stats,
    /// The right tip's deviation, mm.
    pub right: Stats,
    /// The platform's position error, mm.
    pub position: Stats,
    /// The platform's rotation error, deg.
    pub rotation: Stats,
    /// The histogram of the tip deviations.
    pub histogram: Histogram,
    /// The sensitivity ranking (first-order, from the analytic
    /// derivatives), when a [`Linearisation`] was given.
    pub sensitivity: Vec<Sensitivity>,
}

impl Report {
    /// The report of `results`, with the ranking of `linear` under `spec`.
    pub fn new(results: &Results, linear: Option<&Linearisation>, spec: &Spec) -> Self {
        let tip = results
            .left_tip_dev_mm
            .iter()
            .zip(&results.right_tip_dev_mm)
            .map(|(l, r)| l.max(*r));
        Self {
            samples: results.len(),
            failed: results.failures.len(),
            first_failures: results.failures.iter().take(5).copied().collect(),
            tip: Stats::new(tip),
            left: Stats::new(results.left_tip_dev_mm.iter().copied()),
            right: Stats::new(results.right_tip_dev_mm.iter().copied()),
            position: Stats::new(results.pose_position_err_mm.iter().copied()),
            rotation: Stats::new(results.pose_rotation_err_deg.iter().copied()),
            histogram: Histogram::new(results),
            sensitivity: linear.map(|l| l.sensitivity(spec)).unwrap_or_default(),
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} perturbed robots, {} failed ({:.3}%)",
            self.samples,
            self.failed,
            100.0 * self.failed as f64 / self.samples.max(1) as f64
        )?;
        for (sample, why) in &self.first_failures {
            writeln!(f, "  sample {sample} failed {why}")?;
        }
        writeln!(f)?;
        write!(f, "{:<28}", "largest deviation over the motion")?;
        for (p, _) in &self.tip.percentiles {
            write!(f, "{:>11}", format!("p{p}"))?;
        }
        writeln!(f, "{:>11}{:>11}", "mean", "max")?;
        let rows = [
            ("tip, larger of both (mm)", &self.tip),
            ("left tip (mm)", &self.left),
            ("right tip (mm)", &self.right),
            ("platform position (mm)", &self.position),
            ("platform rotation (deg)", &self.rotation),
        ];
        for (name, s) in rows {
            write!(f, "{name:<28}")?;
            for (_, v) in &s.percentiles {
                write!(f, "{v:>11.5}")?;
            }
            writeln!(f, "{:>11.5}{:>11.5}", s.mean, s.max)?;
        }
        if !self.sensitivity.is_empty() {
            writeln!(f)?;
            writeln!(
                f,
                "sensitivity (first order, from the analytic derivatives): each family's share \
                 of the mean-square tip deviation"
            )?;
            for s in &self.sensitivity {
                writeln!(
                    f,
                    "  {:<34}{:>7.1}%   {:.5} mm rms alone",
                    s.family.key(),
                    100.0 * s.share,
                    s.rms_tip_mm
                )?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_are_numpys_linear_ones() {
        // numpy.percentile([1, 2, 3, 4], [50, 95, 99, 99.9]) ->
        // [2.5, 3.85, 3.97, 3.997].
        let v = [1.0, 2.0, 3.0, 4.0];
        let want = [2.5, 3.85, 3.97, 3.997];
        for (p, w) in LEVELS.iter().zip(want) {
            assert!((percentile(&v, *p) - w).abs() < 1e-12, "{p}");
        }
        assert_eq!(percentile(&[7.0], 99.9), 7.0);
        assert!(percentile(&[], 50.0).is_nan());
        let s = Stats::new([3.0, f64::NAN, 1.0, 2.0].into_iter());
        assert_eq!(s.percentiles[0], (50.0, 2.0));
        assert_eq!((s.mean, s.max), (2.0, 3.0));
    }
}
