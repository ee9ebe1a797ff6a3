//! Module 1's inverse kinematics in lanes: the six sliders that put the
//! platform at a pose, as [`ParallelRobot::ik`] computes them (serial
//! singularity and strokes checked).
//!
//! Every operation is the scalar solver's, in its order, on square roots
//! and the kinematics' sine and cosine only: a clean lane gives the scalar
//! path's bits. A lane is **clean** when its angles are within the sine's
//! range, every input is finite, each leg reaches (`disc >= 0`), each leg
//! is past the serial singularity threshold and each slider is within its
//! stroke (finite); any other row is solved again by the scalar
//! [`ParallelRobot::ik`], which gives its values or its typed error.

// Indexed loops over the lanes and the axes are the point (see `lanes`).
#![allow(clippy::needless_range_loop)]

use core::ops::Range;

use parasils_kin::{ParallelRobot, Pose};

use crate::lanes::{M, V};
use crate::level::{Kernel, Level, dispatch};
use crate::rows::{BatchError, OnRowError, Strided, check_input, check_output};
use crate::trig::sincos;

/// Module 1's inverse kinematics over batches of rows, evaluated at a
/// [`Level`] (the widest the CPU has, by default).
#[derive(Debug, Clone, Copy)]
pub struct Module1Ik {
    robot: ParallelRobot<f64>,
    level: Level,
    c: Consts,
}

/// One guide, as every lane needs it.
#[derive(Debug, Clone, Copy)]
struct Leg {
    point: [f64; 3],
    direction: [f64; 3],
    link: f64,
    sign: f64,
    offset: f64,
    stroke: [f64; 2],
}

#[derive(Debug, Clone, Copy)]
struct Consts {
    nodes: [[f64; 3]; 3],
    legs: [Leg; 6],
    serial: f64,
}

impl Module1Ik {
    /// The solver of `robot`, at [`Level::detect`].
    pub fn new(robot: ParallelRobot<f64>) -> Self {
        let g = robot.geometry();
        let legs = g.guides.map(|guide| Leg {
            point: [guide.point.x, guide.point.y, guide.point.z],
            direction: [guide.direction.x, guide.direction.y, guide.direction.z],
            link: guide.link_length,
            sign: guide.branch.sign::<f64>(),
            offset: guide.encoder_offset,
            stroke: [guide.stroke.min, guide.stroke.max],
        });
        let c = Consts {
            nodes: g.nodes.map(|a| [a.x, a.y, a.z]),
            legs,
            serial: g.thresholds.serial,
        };
        Self {
            robot,
            level: Level::detect(),
            c,
        }
    }

    /// The same solver at `level`, or `None` when this CPU lacks it.
    pub fn at_level(self, level: Level) -> Option<Self> {
        level.is_supported().then_some(Self { level, ..self })
    }

    /// The level it runs at.
    pub fn level(&self) -> Level {
        self.level
    }

    /// Solves rows `rows` of `pose` (`x, y, z` mm, `psi, theta, phi` rad):
    /// row `rows.start + k`'s sliders `q1..q6` (mm) go to `out[6k..6k + 6]`
    /// and its success to `ok[k]`; a failing row stops the batch or is NaN
    /// (`on_error`), as [`InstrumentIk::solve`](crate::InstrumentIk::solve).
    pub fn solve(
        &self,
        rows: Range<usize>,
        pose: Strided<'_, 6>,
        out: &mut [f64],
        ok: &mut [bool],
        on_error: OnRowError,
    ) -> Result<(), BatchError> {
        let n = rows.len();
        check_input(&pose, &rows, "pose")?;
        check_output("out", 6 * n, out.len())?;
        check_output("ok", n, ok.len())?;
        dispatch(
            self.level,
            Run {
                ik: self,
                rows,
                pose,
                out,
                ok,
                on_error,
            },
        )
    }

    /// One row by the scalar solver.
    #[inline(never)]
    fn scalar_row(
        &self,
        row: usize,
        pose: [f64; 6],
        out: &mut [f64],
        ok: &mut bool,
        on_error: OnRowError,
    ) -> Result<(), BatchError> {
        let solved = self.robot.ik(&Pose::from_array(pose)).map(|q| q.to_array());
        on_error.write(row, solved, out, ok)
    }
}

struct Run<'a, 'b> {
    ik: &'a Module1Ik,
    rows: Range<usize>,
    pose: Strided<'b, 6>,
    out: &'a mut [f64],
    ok: &'a mut [bool],
    on_error: OnRowError,
}

impl Kernel for Run<'_, '_> {
    type Output = Result<(), BatchError>;

    #[inline(always)]
    fn lanes<const L: usize>(self) -> Self::Output {
        let Run {
            ik,
            rows,
            pose,
            out,
            ok,
            on_error,
        } = self;
        let n = rows.len();
        let mut k = 0;
        while k < n {
            let m = L.min(n - k);
            let p = pose.gather::<L>(rows.start + k, m);
            let (q, clean) = block::<L>(&ik.c, &p);
            for l in 0..m {
                let o = &mut out[6 * (k + l)..6 * (k + l) + 6];
                if clean.get(l) {
                    for (j, v) in o.iter_mut().enumerate() {
                        *v = q[j].0[l];
                    }
                    ok[k + l] = true;
                } else {
                    let row = rows.start + k + l;
                    ik.scalar_row(row, pose.row(row), o, &mut ok[k + l], on_error)?;
                }
            }
            k += L;
        }
        Ok(())
    }

    fn scalar(self) -> Self::Output {
        for (k, (o, flag)) in self
            .out
            .chunks_exact_mut(6)
            .zip(self.ok.iter_mut())
            .enumerate()
        {
            let row = self.rows.start + k;
            self.ik
                .scalar_row(row, self.pose.row(row), o, flag, self.on_error)?;
        }
        Ok(())
    }
}

/// `L` poses in columns: the six sliders in columns, and which lanes are
/// clean (see `ParallelRobot::legs`, `check_serial`, `check_strokes`).
#[inline(always)]
fn block<const L: usize>(c: &Consts, p: &[V<L>; 6]) -> ([V<L>; 6], M<L>) {
    let [x, y, z, psi, theta, phi] = *p;
    // Every input finite: v * 0 is 0 for finite v, NaN otherwise.
    let probe = ((x * 0.0 + y * 0.0) + (z * 0.0 + psi * 0.0)) + (theta * 0.0 + phi * 0.0);
    let mut clean = probe.eq(V::splat(0.0));
    let (s1, c1, in1) = sincos(psi);
    let (s2, c2, in2) = sincos(theta);
    let (s3, c3, in3) = sincos(phi);
    clean = clean & in1 & in2 & in3;
    let r = [
        [c2 * c3, -c2 * s3, s2],
        [c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2],
        [s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2],
    ];
    // rho = R a for each node (nalgebra's product: column by column).
    // Loops, not `map` closures: everything here must inline into the
    // level's target-feature context.
    let mut rho = [[V::splat(0.0); 3]; 3];
    for (n, a) in c.nodes.iter().enumerate() {
        for i in 0..3 {
            rho[n][i] = (r[i][0] * a[0] + r[i][1] * a[1]) + r[i][2] * a[2];
        }
    }
    let position = [x, y, z];
    let mut q = [V::splat(0.0); 6];
    for (j, leg) in c.legs.iter().enumerate() {
        let node = &rho[j / 2];
        let mut rj = [V::splat(0.0); 3];
        for i in 0..3 {
            rj[i] = (position[i] + node[i]) - leg.point[i];
        }
        let d = leg.direction;
        let ru = (rj[0] * d[0] + rj[1] * d[1]) + rj[2] * d[2];
        let mut w = [V::splat(0.0); 3];
        for i in 0..3 {
            w[i] = rj[i] - ru * d[i];
        }
        let dist2 = (w[0] * w[0] + w[1] * w[1]) + w[2] * w[2];
        let disc = leg.link * leg.link - dist2;
        let eu = leg.sign * disc.sqrt();
        let qj = (ru - eu) + leg.offset;
        clean = clean
            & disc.ge(V::splat(0.0))
            & (eu.abs() / leg.link).ge(V::splat(c.serial))
            & qj.abs().lt(V::splat(f64::INFINITY))
            & qj.ge(V::splat(leg.stroke[0]))
            & qj.le(V::splat(leg.stroke[1]));
        q[j] = qj;
    }
    (q, clean)
}
