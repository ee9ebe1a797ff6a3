//! Module 1's forward kinematics: Newton's method on the six link
//! constraints, globalised by continuation from the guess (see the
//! [module docs](crate::parallel), *Forward kinematics*).

use nalgebra::{Matrix3, Vector3};

use super::geometry::FkOptions;
use super::ik::ParallelRobot;
use super::types::{Actuators, FkSolution, actuator_number};
use crate::check::check_results;
use crate::error::{Error, ParallelSingularity};
use crate::frame::Pose;
use crate::linalg::{Svd6, Vec6, norm_squared, transpose};
use crate::real::Real;

impl<T: Real> ParallelRobot<T> {
    /// Forward kinematics with the geometry's stopping rules
    /// ([`ParallelGeometry::fk`](super::ParallelGeometry::fk)): see
    /// [`ParallelRobot::fk_with`].
    pub fn fk(&self, q: &Actuators<T>, guess: &Pose<T>) -> Result<FkSolution<T>, Error> {
        self.fk_with(q, guess, &self.geometry().fk)
    }

    /// Forward kinematics: the pose at which the actuators `q` (mm) hold the
    /// platform, by Newton's method from `guess`, globalised by continuation
    /// (see the [module docs](crate::parallel)). The guess picks the assembly mode: the
    /// solution is the one connected to it; seed it with the previous pose
    /// along a motion. `FkSolution::iterations` counts the Newton steps of
    /// all stages.
    ///
    /// Strokes are not checked (the actuators are measured, not commanded).
    /// Errors: non-finite `q` or guess ([`Error::NonFinite`]); a singular
    /// Jacobian at an iterate ([`Error::SingularJacobian`], parallel or
    /// Euler-angle kind, with the iteration); no convergence within
    /// `options.max_iterations` steps or a diverging iterate
    /// ([`Error::NoConvergence`]); a solution with a link on the other branch
    /// ([`Error::BranchMismatch`]); invalid options
    /// ([`Error::InvalidParameter`]).
    pub fn fk_with(
        &self,
        q: &Actuators<T>,
        guess: &Pose<T>,
        options: &FkOptions<T>,
    ) -> Result<FkSolution<T>, Error> {
        q.check_finite()?;
        guess.check_finite()?;
        if !(options.tolerance > T::zero() && options.tolerance.finite()) {
            return Err(Error::InvalidParameter {
                what: "fk.tolerance",
                value: options.tolerance.to_f64(),
            });
        }
        let guides = &self.geometry().guides;
        let sliders_at = |target: &[T; 6]| -> [Vector3<T>; 6] {
            core::array::from_fn(|j| {
                let g = &guides[j];
                g.point + g.direction * (target[j] - g.encoder_offset)
            })
        };
        let mut budget = Budget {
            used: 0,
            max: options.max_iterations,
        };
        // The homotopy's start: the guess's own actuators, which the guess
        // satisfies exactly. A guess out of reach has none: then a single
        // stage of Newton's method with a line search.
        let Ok(start) = self.legs(&guess.rotation(), &guess.position()) else {
            let (pose, c) = self
                .newton(
                    guess,
                    &sliders_at(&q.0),
                    options.tolerance,
                    false,
                    &mut budget,
                )
                .map_err(|stage| stage.into_error(&budget))?;
            return self.fk_solution(pose, &c, budget.used);
        };
        let stage_tolerance = options.tolerance.max(T::lit(FK_STAGE_TOLERANCE));
        let min_step = T::lit(FK_MIN_CONTINUATION_STEP);
        let (mut x, mut s, mut ds) = (*guess, T::zero(), T::one());
        loop {
            let last = s + ds >= T::one();
            let s_next = if last { T::one() } else { s + ds };
            let target: [T; 6] = if last {
                q.0
            } else {
                core::array::from_fn(|j| start.q[j] + (q[j] - start.q[j]) * s_next)
            };
            let tolerance = if last {
                options.tolerance
            } else {
                stage_tolerance
            };
            match self.newton(&x, &sliders_at(&target), tolerance, true, &mut budget) {
                Ok((pose, c)) => {
                    if last {
                        return self.fk_solution(pose, &c, budget.used);
                    }
                    x = pose;
                    s = s_next;
                    ds = (ds * T::lit(2.0)).min(T::one());
                }
                Err(Stage::NotContracting { residual }) => {
                    ds *= T::lit(0.5);
                    if ds < min_step {
                        return Err(Error::NoConvergence {
                            iterations: budget.used,
                            residual: residual.to_f64(),
                        });
                    }
                }
                Err(stage) => return Err(stage.into_error(&budget)),
            }
        }
    }

    /// The converged pose, after the check of every link's branch.
    pub(super) fn fk_solution(
        &self,
        pose: Pose<T>,
        c: &Constraints<T>,
        iterations: u32,
    ) -> Result<FkSolution<T>, Error> {
        for (j, g) in self.geometry().guides.iter().enumerate() {
            if c.e[j].dot(&g.direction) * g.branch.sign::<T>() < T::zero() {
                return Err(Error::BranchMismatch {
                    actuator: actuator_number(j),
                });
            }
        }
        // A pose that overflowed on the way (a guess at the float type's
        // largest angle, say) can leave a residual that ignores it: refused.
        check_results(&pose.to_array(), "module 1: FK pose (overflow)")?;
        Ok(FkSolution {
            pose,
            iterations,
            residual: c.residual,
        })
    }

    /// Newton's method on the constraints with the sliders at `sliders`, from
    /// `x`, until the residual is at most `tolerance`. With `contract`, every
    /// step must be at most half the previous one (a continuation stage,
    /// retried shorter otherwise); without, a backtracking line search on
    /// the residual keeps each step from leaping away.
    fn newton(
        &self,
        x: &Pose<T>,
        sliders: &[Vector3<T>; 6],
        tolerance: T,
        contract: bool,
        budget: &mut Budget,
    ) -> Result<(Pose<T>, Constraints<T>), Stage<T>> {
        let th = &self.geometry().thresholds;
        let mut x = *x;
        let mut c = self.constraints(&x, sliders);
        let mut previous_step = T::lit(f64::INFINITY);
        loop {
            if !c.residual.finite() {
                return Err(if contract {
                    Stage::NotContracting {
                        residual: T::lit(f64::INFINITY),
                    }
                } else {
                    Stage::Diverged
                });
            }
            if c.residual <= tolerance {
                return Ok((x, c));
            }
            if budget.used >= budget.max {
                return Err(Stage::Exhausted {
                    residual: c.residual,
                });
            }
            let (s1, c1) = x.psi.sin_cos();
            let (s2, c2) = x.theta.sin_cos();
            if !(c2.abs() >= th.euler) {
                return Err(Stage::Singular(Error::SingularJacobian {
                    kind: ParallelSingularity::EulerAngles,
                    iteration: budget.used,
                    margin: c2.abs().to_f64(),
                    threshold: th.euler.to_f64(),
                }));
            }
            let singular = |margin: T| {
                Stage::Singular(Error::SingularJacobian {
                    kind: ParallelSingularity::Parallel,
                    iteration: budget.used,
                    margin: margin.to_f64(),
                    threshold: th.parallel.to_f64(),
                })
            };
            // The decomposition of J itself (its columns), V accumulated.
            let svd = Svd6::of_columns::<true>(transpose(&self.scaled_jacobian_rows(&c.rho, &c.e)));
            let sigma_min = svd.smallest();
            if !(sigma_min >= th.parallel) {
                return Err(singular(sigma_min));
            }
            // The Newton step in (dP, L omega_F), then omega_F to the Euler angles.
            let step = svd.solve(&c.f.map(|f| -f));
            let w = Vector3::new(step[3], step[4], step[5]) / self.length_scale();
            let d_phi = (c1 * w.z - s1 * w.y) / c2;
            let d_theta = c1 * w.y + s1 * w.z;
            let d_psi = w.x - s2 * d_phi;
            let dx = [step[0], step[1], step[2], d_psi, d_theta, d_phi];
            let x0 = x.to_array();
            budget.used += 1;
            if contract {
                let size = norm_squared(&step).sqrt();
                if !(size <= T::lit(0.5) * previous_step) {
                    return Err(Stage::NotContracting {
                        residual: c.residual,
                    });
                }
                previous_step = size;
                x = Pose::from_array(core::array::from_fn(|k| x0[k] + dx[k]));
                c = self.constraints(&x, sliders);
                continue;
            }
            // Backtracking on the merit |f|^2 (Armijo; the Newton step is a
            // descent direction): the full step near the solution.
            let mut alpha = T::one();
            let mut halvings = 0;
            loop {
                let trial = Pose::from_array(core::array::from_fn(|k| x0[k] + dx[k] * alpha));
                let ct = self.constraints(&trial, sliders);
                let armijo = T::one() - T::lit(1e-4) * alpha;
                if ct.merit <= c.merit * armijo || (halvings == 0 && ct.merit <= c.merit) {
                    x = trial;
                    c = ct;
                    break;
                }
                halvings += 1;
                if halvings > FK_MAX_HALVINGS {
                    return Err(Stage::Exhausted {
                        residual: c.residual,
                    });
                }
                alpha *= T::lit(0.5);
            }
        }
    }

    /// The constraints of the forward kinematics at the pose `x`, with the
    /// sliders at `sliders` (mm, fixed frame).
    pub(super) fn constraints(&self, x: &Pose<T>, sliders: &[Vector3<T>; 6]) -> Constraints<T> {
        self.constraints_at(&x.position(), &x.rotation(), sliders)
    }

    /// [`Self::constraints`] at the position `p` and the rotation `r`
    /// computed beforehand.
    #[inline]
    pub(super) fn constraints_at(
        &self,
        p: &Vector3<T>,
        r: &Matrix3<T>,
        sliders: &[Vector3<T>; 6],
    ) -> Constraints<T> {
        let rho = self.node_arms(r);
        let p = *p;
        let mut e = [Vector3::zeros(); 6];
        let mut f = [T::zero(); 6];
        let mut residual = T::zero();
        let mut merit = T::zero();
        for (j, g) in self.geometry().guides.iter().enumerate() {
            e[j] = p + rho[j / 2] - sliders[j];
            f[j] = (e[j].norm_squared() - g.link_length * g.link_length)
                / (T::lit(2.0) * g.link_length);
            let relative = f[j] / g.link_length;
            residual = residual.max(relative.abs());
            merit += relative * relative;
        }
        Constraints {
            rho,
            e,
            f,
            residual,
            merit,
        }
    }
}

/// The forward kinematics' constraints at one iterate.
pub(super) struct Constraints<T: Real> {
    /// `R a_i`, mm, fixed frame.
    pub(super) rho: [Vector3<T>; 3],
    /// `e_j = A_i - B_j`, mm, fixed frame.
    pub(super) e: [Vector3<T>; 6],
    /// `f_j = (|e_j|^2 - l_j^2) / (2 l_j)`, mm.
    pub(super) f: Vec6<T>,
    /// `max_j |f_j| / l_j`.
    pub(super) residual: T,
    /// `sum_j (f_j / l_j)^2`, the line search's merit.
    pub(super) merit: T,
}

/// The most halvings of a Newton step in the line search (a step of 2^-30).
const FK_MAX_HALVINGS: u32 = 30;

/// The residual (relative) to which the intermediate stages of the
/// continuation are solved: near enough to the path for the next stage.
const FK_STAGE_TOLERANCE: f64 = 1e-8;

/// The shortest continuation step (a fraction of the way from the guess's
/// actuators to the target) before the forward kinematics gives up.
const FK_MIN_CONTINUATION_STEP: f64 = 1.0 / 1024.0;

/// The Newton steps used and allowed, over all stages.
struct Budget {
    used: u32,
    max: u32,
}

/// How a stage of Newton's method ended without converging.
enum Stage<T> {
    /// A step not at most half the previous one (or a non-finite residual):
    /// the stage was too long.
    NotContracting {
        /// The residual before the step.
        residual: T,
    },
    /// A non-finite residual, without continuation.
    Diverged,
    /// The iteration budget is spent, or the line search failed.
    Exhausted {
        /// The last residual.
        residual: T,
    },
    /// A singular Jacobian: the error to report.
    Singular(Error),
}

impl<T: Real> Stage<T> {
    fn into_error(self, budget: &Budget) -> Error {
        match self {
            Stage::NotContracting { residual } | Stage::Exhausted { residual } => {
                Error::NoConvergence {
                    iterations: budget.used,
                    residual: residual.to_f64(),
                }
            }
            Stage::Diverged => Error::NoConvergence {
                iterations: budget.used,
                residual: f64::INFINITY,
            },
            Stage::Singular(e) => e,
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::parallel::ParallelGeometry;

    /// The fuzzer's case (f32): a guess at theta = f32::MAX (finite) and a
    /// fuzzed guide and node; the FK used to return `Ok` with theta = inf
    /// (and a residual of 0). Now a non-finite pose is an error.
    #[test]
    fn an_fk_pose_that_overflows_is_refused() {
        let mut g = ParallelGeometry::<f32>::assumed();
        let guide = &mut g.guides[3];
        guide.point = Vector3::new(1e-19, 1e-19, 1e-19);
        guide.direction = Vector3::new(1e-19, 1e-19, 1.0);
        guide.link_length = 1e19;
        guide.encoder_offset = 9.352_152e-39;
        g.nodes[0] = Vector3::new(-0.040_283_203, 1e-19, 1e-19);
        g.thresholds.serial = 1e-19;
        g.thresholds.parallel = 1e-19;
        g.fk = FkOptions {
            tolerance: 2.351_057e-38,
            max_iterations: 95,
        };
        let robot = ParallelRobot::new(g).expect("a valid geometry");
        let q = Actuators([3.984_375, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let guess = Pose::from_array([-0.040_283_203, 1e-19, 1e-19, 1e-19, f32::MAX, 7.16e-43]);
        let r = robot.fk(&q, &guess);
        match r {
            Ok(s) => assert!(s.pose.to_array().iter().all(|v| v.is_finite()), "{s:?}"),
            Err(e) => assert!(matches!(e, Error::NonFinite { .. }), "{e:?}"),
        }
    }
}
