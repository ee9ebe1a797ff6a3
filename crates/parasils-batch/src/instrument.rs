//! The instrument modules' inverse kinematics in lanes: the joints that put
//! a module's tip at a point of the fixed frame with the platform at a
//! pose, as [`Instrument::ik`] computes them (joint limits checked).
//!
//! Each lane follows the scalar solver's operations in its order, so the
//! platform's rotation, the tip in the module's frame and `qs3` have the
//! scalar path's bits; `qs2` and `qs1` come from the lanes' `atan2`
//! (`qs2 = atan2(sin qs2, +-cos qs2)`, the scalar path's `asin` or its
//! supplement) within 2 ulps of the scalar path's (`tests/agreement.rs`).
//!
//! A lane is **clean** when every input is finite, the angles are within the
//! sine's range (`|angle| < 2^19` rad), the tip is strictly inside the
//! reach (`|sin qs2| <= 1`, no clamping), past both singularity thresholds,
//! and each joint is inside its limits by more than [`LIMIT_GUARD_RAD`]
//! (`qs1`, `qs2`) or at all (`qs3`, exact). Every other row is solved again
//! by the scalar [`Instrument::ik`], which gives its values or its typed
//! error: a row's error, and whether it has one, are the scalar path's.

use core::ops::Range;

use parasils_kin::nalgebra::Vector3;
use parasils_kin::{AssemblyMode, Instrument, Pose, Real, Side};

use crate::lanes::{M, V};
use crate::level::{Kernel, Level, dispatch};
use crate::rows::{BatchError, OnRowError, Strided, check_input, check_output};
use crate::trig::{atan2, sincos};

/// How far inside its limits (rad) a lane's `qs1` and `qs2` must be for the
/// lane's value to stand; closer rows are solved by the scalar path, so a
/// row at a limit gets the scalar path's decision. The lanes' angles are
/// within 2 ulps (below `1e-15` rad) of the scalar path's.
pub const LIMIT_GUARD_RAD: f64 = 1e-12;

/// The inverse kinematics of one instrument module over batches of rows,
/// evaluated at a [`Level`] (the widest the CPU has, by default).
#[derive(Debug, Clone, Copy)]
pub struct InstrumentIk {
    module: Instrument<f64>,
    mode: AssemblyMode,
    level: Level,
    c: Consts,
}

/// What every lane needs of the module.
#[derive(Debug, Clone, Copy)]
struct Consts {
    sa: f64,
    ca: f64,
    sb: f64,
    cb: f64,
    rcm: [f64; 3],
    right: bool,
    mode_b: bool,
    th_qs3: f64,
    th_cos: f64,
    qs1: [f64; 2],
    qs2: [f64; 2],
    qs3: [f64; 2],
}

impl InstrumentIk {
    /// The solver of `module` in assembly mode `mode`, at [`Level::detect`].
    pub fn new(module: Instrument<f64>, mode: AssemblyMode) -> Self {
        let g = module.geometry();
        let (sa, ca) = g.alpha.sincos();
        let (sb, cb) = g.beta.sincos();
        let l = &g.limits;
        let c = Consts {
            sa,
            ca,
            sb,
            cb,
            rcm: [g.rcm.x, g.rcm.y, g.rcm.z],
            right: g.side == Side::Right,
            mode_b: mode == AssemblyMode::B,
            th_qs3: g.thresholds.qs3,
            th_cos: g.thresholds.cos_qs2,
            qs1: [l.qs1.min + LIMIT_GUARD_RAD, l.qs1.max - LIMIT_GUARD_RAD],
            qs2: [l.qs2.min + LIMIT_GUARD_RAD, l.qs2.max - LIMIT_GUARD_RAD],
            qs3: [l.qs3.min, l.qs3.max],
        };
        Self {
            module,
            mode,
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

    /// The module.
    pub fn module(&self) -> &Instrument<f64> {
        &self.module
    }

    /// Solves rows `rows` of `pose` (`x, y, z` mm, `psi, theta, phi` rad)
    /// and `tip` (mm, fixed frame): row `rows.start + k`'s joints
    /// (`qs1`, `qs2` rad in `(-pi, pi]`, `qs3` mm) go to `out[3k..3k + 3]`
    /// and its success to `ok[k]`.
    ///
    /// A failing row stops the batch with its error ([`OnRowError::Stop`],
    /// rows before it written) or is NaN with `ok[k] = false`
    /// ([`OnRowError::Nan`]). Fails with [`BatchError::Shape`] when an
    /// input lacks a row or `out`, `ok` are not `3 n` and `n` long.
    pub fn solve(
        &self,
        rows: Range<usize>,
        pose: Strided<'_, 6>,
        tip: Strided<'_, 3>,
        out: &mut [f64],
        ok: &mut [bool],
        on_error: OnRowError,
    ) -> Result<(), BatchError> {
        let n = rows.len();
        check_input(&pose, &rows, "pose")?;
        check_input(&tip, &rows, "tip")?;
        check_output("out", 3 * n, out.len())?;
        check_output("ok", n, ok.len())?;
        dispatch(
            self.level,
            Run {
                ik: self,
                rows,
                pose,
                tip,
                out,
                ok,
                on_error,
            },
        )
    }

    /// One row by the scalar solver, written at `k`.
    #[inline(never)]
    fn scalar_row(
        &self,
        row: usize,
        pose: [f64; 6],
        tip: [f64; 3],
        out: &mut [f64],
        ok: &mut bool,
        on_error: OnRowError,
    ) -> Result<(), BatchError> {
        let solved = self
            .module
            .ik(&Pose::from_array(pose), &Vector3::from(tip), self.mode)
            .map(|q| q.to_array());
        on_error.write(row, solved, out, ok)
    }
}

struct Run<'a, 'b> {
    ik: &'a InstrumentIk,
    rows: Range<usize>,
    pose: Strided<'b, 6>,
    tip: Strided<'b, 3>,
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
            tip,
            out,
            ok,
            on_error,
        } = self;
        let n = rows.len();
        let mut k = 0;
        while k < n {
            let m = L.min(n - k);
            // Columns of L rows; a short last block repeats its last row.
            let p = pose.gather::<L>(rows.start + k, m);
            let t = tip.gather::<L>(rows.start + k, m);
            let (q, clean) = block::<L>(&ik.c, &p, &t);
            for l in 0..m {
                let o = &mut out[3 * (k + l)..3 * (k + l) + 3];
                if clean.get(l) {
                    o.copy_from_slice(&[q[0].0[l], q[1].0[l], q[2].0[l]]);
                    ok[k + l] = true;
                } else {
                    let row = rows.start + k + l;
                    ik.scalar_row(
                        row,
                        pose.row(row),
                        tip.row(row),
                        o,
                        &mut ok[k + l],
                        on_error,
                    )?;
                }
            }
            k += L;
        }
        Ok(())
    }

    fn scalar(self) -> Self::Output {
        for (k, (o, flag)) in self
            .out
            .chunks_exact_mut(3)
            .zip(self.ok.iter_mut())
            .enumerate()
        {
            let row = self.rows.start + k;
            self.ik.scalar_row(
                row,
                self.pose.row(row),
                self.tip.row(row),
                o,
                flag,
                self.on_error,
            )?;
        }
        Ok(())
    }
}

/// `L` rows (pose and tip in columns): the joints `[qs1, qs2, qs3]` in
/// columns, and which lanes are clean. The scalar solver's operations in
/// its order (see `Instrument::ik_local` and `Pose::rotation`), selects
/// for its branches.
#[inline(always)]
fn block<const L: usize>(c: &Consts, p: &[V<L>; 6], t: &[V<L>; 3]) -> ([V<L>; 3], M<L>) {
    let [x, y, z, psi, theta, phi] = *p;
    let [t0, t1, t2] = *t;
    // Every input finite: v * 0 is 0 for finite v, NaN otherwise.
    let probe = ((x * 0.0 + y * 0.0) + (z * 0.0 + psi * 0.0))
        + ((theta * 0.0 + phi * 0.0) + ((t0 * 0.0 + t1 * 0.0) + t2 * 0.0));
    let finite = probe.eq(V::splat(0.0));
    // R = R_X(psi) R_Y(theta) R_Z(phi), as parasils-kin's `rotation`.
    let (s1, c1, in1) = sincos(psi);
    let (s2, c2, in2) = sincos(theta);
    let (s3, c3, in3) = sincos(phi);
    let r00 = c2 * c3;
    let r01 = -c2 * s3;
    let r02 = s2;
    let r10 = c1 * s3 + s1 * s2 * c3;
    let r11 = c1 * c3 - s1 * s2 * s3;
    let r12 = -s1 * c2;
    let r20 = s1 * s3 - c1 * s2 * c3;
    let r21 = s1 * c3 + c1 * s2 * s3;
    let r22 = c1 * c2;
    // R^T (tip - P) - RCM (nalgebra's dot: (a + b) + c).
    let (d0, d1, d2) = (t0 - x, t1 - y, t2 - z);
    let l0 = (r00 * d0 + r10 * d1 + r20 * d2) - c.rcm[0];
    let l1 = (r01 * d0 + r11 * d1 + r21 * d2) - c.rcm[1];
    let l2 = (r02 * d0 + r12 * d1 + r22 * d2) - c.rcm[2];
    // The left convention.
    let px = if c.right { -l0 } else { l0 };
    let (py, pz) = (l1, l2);
    let qs3 = (px * px + py * py + pz * pz).sqrt();
    let nq = -qs3;
    let (vx0, vy, vz0) = (px / nq, py / nq, pz / nq);
    // R_Y(-alpha) v.
    let vx = c.ca * vx0 - c.sa * vz0;
    let vz = c.sa * vx0 + c.ca * vz0;
    let sin_qs2 = vx / c.cb;
    let inside = sin_qs2.abs().le(V::splat(1.0));
    let cos_qs2 = ((1.0 - sin_qs2) * (1.0 + sin_qs2)).sqrt();
    // qs2: asin in mode A, its supplement in mode B (+pi for sin qs2 = -0,
    // as the scalar path: -0 + 0 = +0).
    let (cos_qs2, qs2) = if c.mode_b {
        let neg = -cos_qs2;
        (neg, atan2(sin_qs2 + 0.0, neg))
    } else {
        (cos_qs2, atan2(sin_qs2, cos_qs2))
    };
    let (sb, cb) = (c.sb, c.cb);
    let ay = -sb * vz - cb * cos_qs2 * vy;
    let ax = cb * cos_qs2 * vz - sb * vy;
    let qs1 = atan2(ay, ax);
    let zero = V::splat(0.0);
    let clean = finite
        & in1
        & in2
        & in3
        & qs3.ge(V::splat(c.th_qs3))
        & qs3.lt(V::splat(f64::INFINITY))
        & inside
        & cos_qs2.abs().ge(V::splat(c.th_cos))
        & (ax.abs().gt(zero) | ay.abs().gt(zero))
        & qs1.ge(V::splat(c.qs1[0]))
        & qs1.le(V::splat(c.qs1[1]))
        & qs2.ge(V::splat(c.qs2[0]))
        & qs2.le(V::splat(c.qs2[1]))
        & qs3.ge(V::splat(c.qs3[0]))
        & qs3.le(V::splat(c.qs3[1]));
    ([qs1, qs2, qs3], clean)
}
