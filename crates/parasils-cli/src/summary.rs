//! A run's summary for people: ranges and peak rates of every actuator and
//! joint, the largest tip drift, the smallest margins. Accumulated sample by
//! sample, in constant memory.

use core::fmt;

use crate::sample::{COLUMNS, NUM_COLUMNS, Sample, Sink};

/// Running extremes of every column of [`COLUMNS`].
#[derive(Debug, Clone)]
pub struct Summary {
    count: usize,
    min: [f64; NUM_COLUMNS],
    max: [f64; NUM_COLUMNS],
    /// Whether module 1 runs on the assumed default geometry.
    pub module1_assumed: bool,
}

impl Default for Summary {
    fn default() -> Self {
        Self {
            count: 0,
            min: [f64::INFINITY; NUM_COLUMNS],
            max: [f64::NEG_INFINITY; NUM_COLUMNS],
            module1_assumed: false,
        }
    }
}

impl Sink for Summary {
    type Error = core::convert::Infallible;

    fn push(&mut self, sample: &Sample) -> Result<(), Self::Error> {
        self.count += 1;
        for (i, v) in sample.row().into_iter().enumerate() {
            self.min[i] = self.min[i].min(v);
            self.max[i] = self.max[i].max(v);
        }
        Ok(())
    }
}

impl Summary {
    fn index(column: &str) -> usize {
        COLUMNS.iter().position(|c| *c == column).unwrap_or(0)
    }

    /// The number of samples seen.
    pub fn count(&self) -> usize {
        self.count
    }

    /// `(min, max)` of a column by name (`None` for an unknown column or no samples).
    pub fn range(&self, column: &str) -> Option<(f64, f64)> {
        let i = COLUMNS.iter().position(|c| *c == column)?;
        (self.count > 0).then_some((self.min[i], self.max[i]))
    }

    /// The largest absolute value of a column.
    pub fn peak(&self, column: &str) -> Option<f64> {
        self.range(column).map(|(lo, hi)| lo.abs().max(hi.abs()))
    }

    /// The largest tip drift of both modules, mm.
    pub fn largest_tip_drift(&self) -> f64 {
        let l = self.max[Self::index("left_tip_err_mm")];
        let r = self.max[Self::index("right_tip_err_mm")];
        l.max(r)
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = |c: &str| self.range(c).unwrap_or((f64::NAN, f64::NAN));
        let p = |c: &str| self.peak(c).unwrap_or(f64::NAN);
        let (t0, t1) = r("t_s");
        writeln!(
            f,
            "duration {:.3} s, {} samples ({:.3} to {:.3} s)",
            t1 - t0,
            self.count,
            t0,
            t1
        )?;
        writeln!(f, "platform")?;
        for a in ["psi", "theta"] {
            let (lo, hi) = r(&format!("{a}_deg"));
            writeln!(
                f,
                "  {a:<6} {lo:>9.4} .. {hi:>9.4} deg    peak rate {:>8.4} deg/s    peak acc {:>8.4} deg/s^2",
                p(&format!("{a}_rate_deg_s")),
                p(&format!("{a}_acc_deg_s2"))
            )?;
        }
        writeln!(f, "module 1 actuators")?;
        if self.module1_assumed {
            writeln!(
                f,
                "  (module 1 uses the ASSUMED default geometry: the real robot's dimensions are not published; pass --robot FILE.toml)"
            )?;
        }
        for j in 1..=6 {
            let (lo, hi) = r(&format!("q{j}_mm"));
            writeln!(
                f,
                "  q{j}     {lo:>9.4} .. {hi:>9.4} mm     peak rate {:>8.4} mm/s     peak acc {:>8.4} mm/s^2",
                p(&format!("q{j}_rate_mm_s")),
                p(&format!("q{j}_acc_mm_s2"))
            )?;
        }
        for side in ["left", "right"] {
            writeln!(f, "{side} instrument")?;
            for (joint, unit) in [("qs1", "deg"), ("qs2", "deg"), ("qs3", "mm")] {
                let (lo, hi) = r(&format!("{side}_{joint}_{unit}"));
                let rate_unit = if unit == "deg" { "deg/s" } else { "mm/s" };
                let rate_col = format!("{side}_{joint}_rate_{}", rate_unit.replace('/', "_"));
                writeln!(
                    f,
                    "  {joint}    {lo:>9.4} .. {hi:>9.4} {unit:<3}    peak rate {:>8.4} {rate_unit}",
                    p(&rate_col)
                )?;
            }
        }
        writeln!(
            f,
            "largest tip drift {:.3e} mm (left {:.3e}, right {:.3e})",
            self.largest_tip_drift(),
            self.max[Self::index("left_tip_err_mm")],
            self.max[Self::index("right_tip_err_mm")]
        )?;
        let cos_l = r("left_cos_qs2");
        let cos_r = r("right_cos_qs2");
        write!(
            f,
            "smallest margins: |cos qs2| left {:.4}, right {:.4}; module 1 serial {:.4}, parallel {:.4}",
            cos_l.0.abs().min(cos_l.1.abs()),
            cos_r.0.abs().min(cos_r.1.abs()),
            r("module1_serial_margin").0,
            r("module1_parallel_margin").0
        )
    }
}
