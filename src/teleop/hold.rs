//! Limits held, never an error: a cycle's candidate motion is checked at
//! the setpoint it reaches and at the point where the robot would come to
//! rest if it braked from there; a candidate that would cross a limit is
//! reduced to a fraction of the way from the controlled stop to it,
//! predicted by regula falsi on the limiting margin or gap and verified by
//! the same checks (see `docs/model.md`, *Teleoperation*).

use crate::kin::nalgebra::Vector3;
use crate::kin::{
    Actuator, Bodies, Clearance, ClearancePair, ControlStep, LimitError, MarginTracker,
    ModuleCommand, PlatformState, Pose, RateKind, Real, Side, TipMotion, TipTargets, step_rates,
};
use crate::supervisor::{Margin, Margins};

use super::core::{Teleop, Velocities};
use super::cycle::{Fault, HoldAt};

/// How many predicted fractions the search verifies at most before it
/// checks the controlled stop (each failure narrows the bracket; the search
/// ends at the first that passes).
const TRIES: usize = 2;

/// The share of the way to the predicted crossing the search aims at: the
/// limiting slack is aimed at a fifth of its value at the current setpoint,
/// so a curved margin rarely makes the prediction fail.
const AIM: f64 = 0.8;

/// The parts of the motion a limit belongs to: `[left tip, right tip,
/// view]`.
fn culprits(reason: &HoldAt) -> [bool; 3] {
    match reason {
        HoldAt::Margin(m) => match m {
            Margin::LeftCosQs2
            | Margin::LeftQs3
            | Margin::LeftAngleLimits
            | Margin::LeftQs3Limits => [true, false, true],
            Margin::RightCosQs2
            | Margin::RightQs3
            | Margin::RightAngleLimits
            | Margin::RightQs3Limits => [false, true, true],
            Margin::Serial | Margin::Parallel | Margin::Stroke => [true; 3],
        },
        HoldAt::Clearance(ClearancePair::LeftEndoscope) => [true, false, true],
        HoldAt::Clearance(ClearancePair::RightEndoscope) => [false, true, true],
        HoldAt::Actuator {
            actuator: Actuator::Instrument { side, .. },
            ..
        } => match side {
            Side::Left => [true, false, true],
            Side::Right => [false, true, true],
        },
        HoldAt::Clearance(_) | HoldAt::Reach(_) | HoldAt::Actuator { .. } => [true; 3],
    }
}

/// The three gaps of `c`, in the order of [`ClearancePair::ALL`], mm.
pub(super) fn gap_array<T: Real>(c: &Clearance<T>) -> [T; 3] {
    ClearancePair::ALL.map(|pair| c.get(pair).gap)
}

/// How many units in the last place of a margin or gap its solve's
/// rounding may leave between two solves of one pose.
const ROUNDING_ULPS: f64 = 64.0;

/// `x` lowered by [`ROUNDING_ULPS`] of its magnitude: a threshold the
/// checks accept to rounding. A setpoint resting on a threshold, or a stop
/// ending on it, computes its margin a few units in the last place either
/// side of it from one cycle to the next; without this the hold would
/// refuse every fraction and fall back to the stop for a difference no
/// motion makes. The allowance does not accumulate: it is taken off the
/// threshold itself, never off the current value (a robot below a
/// threshold may only move away from it).
fn rounded_down<T: Real>(x: T) -> T {
    x - x.abs().max(T::one()) * T::EPSILON * T::lit(ROUNDING_ULPS)
}

/// The lowest value on `[0, 1]` of the parabola through `(0, a)`,
/// `(1/2, b)`, `(1, c)`: the smallest of the three, or the vertex when it
/// is a minimum inside.
fn dip<T: Real>(a: T, b: T, c: T) -> T {
    let lowest = a.min(b).min(c);
    let curve = (c - b - b + a) * T::lit(2.0);
    let slope = c - a - curve;
    if curve > T::zero() {
        let s = -slope / (curve + curve);
        if s > T::zero() && s < T::one() {
            return lowest.min(a - slope * slope / (T::lit(4.0) * curve));
        }
    }
    lowest
}

/// A candidate that failed: the limit it would cross, and by how much
/// where it was found (see [`Teleop::slack`]; none for a reach failure).
#[derive(Clone, Copy)]
struct Miss<T: Real> {
    at: HoldAt,
    slack: Option<T>,
}

impl<T: Real> Miss<T> {
    fn reach(e: crate::kin::Error) -> Self {
        Self {
            at: HoldAt::Reach(e),
            slack: None,
        }
    }
}

/// A candidate cycle solved.
struct Trial<T: Real> {
    tips: [Vector3<T>; 2],
    pose: Pose<T>,
    step: ControlStep<T>,
    margins: Margins<T>,
    clearance: Option<Clearance<T>>,
    tracker: MarginTracker<T>,
    end_tracker: MarginTracker<T>,
    mid_tracker: MarginTracker<T>,
    /// The stop from it the checks covered, s (none when unchecked).
    stop_s: Option<T>,
    /// The lowest margins and gaps its checks found, at the setpoint or
    /// along the stop line.
    path_low: (Margins<T>, Option<[T; 3]>),
}

impl<T: Real> Teleop<T> {
    /// The gaps between the bodies at `step`, when the core watches them.
    pub(super) fn clearance_of(
        &self,
        step: &ControlStep<T>,
    ) -> Result<Option<Clearance<T>>, crate::kin::Error> {
        let Some((bodies, _)) = &self.watch else {
            return Ok(None);
        };
        let c = &self.controller;
        Bodies::at(
            bodies,
            &step.frame,
            &c.left,
            &step.left.q,
            &c.right,
            &step.right.q,
            self.depth,
        )?
        .clearance()
        .map(Some)
    }

    /// Margins and gaps each at or above its stop threshold, or no lower
    /// than at the current setpoint (a robot stopped near a limit may move
    /// away from it).
    fn admissible(&self, m: &Margins<T>, gaps: Option<[T; 3]>) -> Result<(), Miss<T>> {
        for k in Margin::ALL {
            if !(m[k] >= rounded_down(self.supervisor.stop[k])) && !(m[k] >= self.margins[k]) {
                return Err(Miss {
                    at: HoldAt::Margin(k),
                    slack: self.slack(HoldAt::Margin(k), m, gaps),
                });
            }
        }
        if let (Some((_, th)), Some(gaps), Some(now)) = (&self.watch, gaps, &self.clearance) {
            for (pair, g) in ClearancePair::ALL.into_iter().zip(gaps) {
                if !(g >= rounded_down(th.stop)) && !(g >= now.get(pair).gap) {
                    let at = HoldAt::Clearance(pair);
                    return Err(Miss {
                        at,
                        slack: self.slack(at, m, Some(gaps)),
                    });
                }
            }
        }
        Ok(())
    }

    /// Every actuator's velocity and acceleration at `step` within its
    /// limit; the first beyond it is the miss, its slack `1 - |rate| /
    /// limit`.
    fn within_limits(&self, step: &ControlStep<T>) -> Result<(), Miss<T>> {
        let (q_dot, q_ddot) = step_rates(step);
        match self.controller.limits.check_rates(&q_dot, &q_ddot) {
            Ok(()) => Ok(()),
            Err(LimitError::Exceeded {
                actuator,
                kind,
                value,
                limit,
            }) => Err(Miss {
                at: HoldAt::Actuator { actuator, kind },
                slack: (value.is_finite() && limit > 0.0)
                    .then(|| T::one() - T::lit(value.abs() / limit)),
            }),
            // `check_rates` reports nothing else; a limit the controller
            // was built with is valid.
            Err(_) => Ok(()),
        }
    }

    /// How far the margin or gap `at` of `m` and `gaps` is above the lower
    /// of its stop threshold and its value at the current setpoint (mm or
    /// the margin's unit; negative: it fails), when it is finite. For an
    /// actuator's velocity, its share of the limit left at the current
    /// setpoint, `1 - |q_dot| / q_dot_max`; none for an acceleration (the
    /// current one says nothing of the stop's).
    fn slack(&self, at: HoldAt, m: &Margins<T>, gaps: Option<[T; 3]>) -> Option<T> {
        let x = match at {
            HoldAt::Actuator {
                actuator,
                kind: RateKind::Velocity,
            } => {
                let k = actuator.index();
                let (q_dot, _) = step_rates(&self.step);
                let limit = *self.controller.limits.velocity.get(k)?;
                T::one() - q_dot.get(k)?.abs() / limit
            }
            HoldAt::Actuator { .. } => return None,
            HoldAt::Margin(k) => m[k] - self.supervisor.stop[k].min(self.margins[k]),
            HoldAt::Clearance(pair) => {
                let (Some((_, th)), Some(gaps), Some(now)) = (&self.watch, gaps, &self.clearance)
                else {
                    return None;
                };
                let i = ClearancePair::ALL.iter().position(|p| *p == pair)?;
                *gaps.get(i)? - th.stop.min(now.get(pair).gap)
            }
            HoldAt::Reach(_) => return None,
        };
        x.is_finite().then_some(x)
    }

    /// The cycle reached with the velocities `v` over `dt`, solved; with
    /// `check`, it and its stopping point must be admissible.
    fn trial(&self, dt: T, v: &Velocities<T>, check: bool) -> Result<Trial<T>, Miss<T>> {
        let per_s = if dt > T::zero() {
            T::one() / dt
        } else {
            T::zero()
        };
        let tips = [0, 1].map(|m| self.tips[m] + v.tips[m] * dt);
        let pose = Pose {
            psi: self.pose.psi + v.angles[0] * dt,
            theta: self.pose.theta + v.angles[1] * dt,
            ..self.pose
        };
        let acc = [0, 1].map(|i| (v.angles[i] - self.velocity.angles[i]) * per_s);
        let platform = PlatformState::reorientation(pose, v.angles, acc);
        let command = |m: usize| {
            ModuleCommand::Tip(TipMotion {
                position: tips[m],
                velocity: v.tips[m],
                acceleration: (v.tips[m] - self.velocity.tips[m]) * per_s,
            })
        };
        let mut tracker = self.tracker;
        // Matched, not `map_err`: the step is taken out of the kinematics'
        // `Result` once, never moved into a second one.
        let step =
            match self
                .controller
                .step_commanded(&platform, &command(0), &command(1), &mut tracker)
            {
                Ok(step) => step,
                Err(e) => return Err(Miss::reach(e)),
            };
        let margins = Margins::of(&step);
        let clearance = self.clearance_of(&step).map_err(Miss::reach)?;
        let mut end_tracker = self.end_tracker;
        let mut mid_tracker = self.mid_tracker;
        let mut stop_s = None;
        let mut path_low = (margins, clearance.as_ref().map(gap_array));
        if check {
            let gaps = clearance.as_ref().map(gap_array);
            self.admissible(&margins, gaps)?;
            self.within_limits(&step)?;
            if !v.is_zero() {
                // The controlled stop from this setpoint keeps to the line
                // from it to `x + v (T_stop / 2 + dt)` (one cycle late):
                // solved at its middle and its end, and each margin and gap
                // checked there and at the lowest point of the parabola
                // through its three values (a dip between the points).
                let t_stop = self.stop_time(v, &step);
                stop_s = Some(t_stop);
                let reach = t_stop * T::lit(0.5) + dt;
                let mut along = [(margins, gaps); 3];
                for (i, s) in [(2, T::one()), (1, T::lit(0.5))] {
                    let k = reach * s;
                    let ends = [0, 1].map(|m| tips[m] + v.tips[m] * k);
                    let end_pose = Pose {
                        psi: pose.psi + v.angles[0] * k,
                        theta: pose.theta + v.angles[1] * k,
                        ..pose
                    };
                    let end = self
                        .controller
                        .step(
                            &PlatformState::at_rest(end_pose),
                            &TipTargets {
                                left: ends[0],
                                right: ends[1],
                            },
                            if i == 2 {
                                &mut end_tracker
                            } else {
                                &mut mid_tracker
                            },
                        )
                        .map_err(Miss::reach)?;
                    let g = self.clearance_of(&end).map_err(Miss::reach)?;
                    along[i] = (Margins::of(&end), g.as_ref().map(gap_array));
                    self.admissible(&along[i].0, along[i].1)?;
                }
                let mut lowest = (margins, gaps);
                for (k, x) in lowest.0.0.iter_mut().enumerate() {
                    *x = dip(along[0].0.0[k], along[1].0.0[k], along[2].0.0[k]);
                }
                lowest.1 = match (along[0].1, along[1].1, along[2].1) {
                    // Zipped, not indexed: no bounds check is left to panic.
                    (Some(mut a), Some(b), Some(c)) => {
                        for ((x, y), z) in a.iter_mut().zip(b).zip(c) {
                            *x = dip(*x, y, z);
                        }
                        Some(a)
                    }
                    _ => None,
                };
                self.admissible(&lowest.0, lowest.1)?;
                path_low = lowest;
            }
        }
        Ok(Trial {
            tips,
            pose,
            step,
            margins,
            clearance,
            tracker,
            end_tracker,
            mid_tracker,
            stop_s,
            path_low,
        })
    }

    /// A fraction `s` of the way from the stop `brake` to `candidate` in
    /// the parts `which` that passes, `miss` being how the whole way
    /// (`s = 1`) fails. The limiting slack is interpolated linearly between
    /// the last fraction that passed (at first `s = 0`, its slack taken from
    /// the current setpoint's margins and gaps) and the last that failed,
    /// and the fraction where it falls to a fifth of its passing value is
    /// solved and checked (regula falsi; halving when the failure has no
    /// slack): the first that passes is taken, at most [`TRIES`] times.
    /// Else the stop in these parts (`s = 0`), checked; none when it fails,
    /// or when a limit these parts do not move fails first.
    fn search(
        &self,
        dt: T,
        brake: &Velocities<T>,
        candidate: &Velocities<T>,
        which: [bool; 3],
        miss: Miss<T>,
    ) -> Option<(Trial<T>, Velocities<T>)> {
        // At `s = 0` the robot follows the stop the current setpoint was
        // checked with: its lowest values are the slack there.
        let now = self.path_low;
        let (mut hi, mut miss) = (T::one(), miss);
        for _ in 0..TRIES {
            let s = match (self.slack(miss.at, &now.0, now.1), miss.slack) {
                (Some(good), Some(bad)) if good > T::zero() && bad < T::zero() => {
                    hi * (good / (good - bad)) * T::lit(AIM)
                }
                (Some(good), _) if !(good > T::zero()) => break,
                _ => hi * T::lit(0.5),
            };
            if !(s > T::zero() && s < hi) {
                break;
            }
            let v = brake.lerp(candidate, s, which);
            match self.trial(dt, &v, true) {
                Ok(trial) => return Some((trial, v)),
                Err(m) => (hi, miss) = (s, m),
            }
            let parts = culprits(&miss.at);
            if parts.iter().zip(which).any(|(&p, w)| p && !w) {
                return None;
            }
        }
        let v = brake.lerp(candidate, T::zero(), which);
        Some((self.trial(dt, &v, true).ok()?, v))
    }

    /// Takes `trial`, moving at `v`, as the new setpoint. A stop from it
    /// may take at most the time its checks covered; after an unchecked
    /// cycle (the controlled stop's), what is left of the stop under way.
    fn commit(&mut self, dt: T, trial: Trial<T>, v: Velocities<T>) {
        self.stop_left = if v.is_zero() {
            None
        } else {
            Some(trial.stop_s.unwrap_or_else(|| self.brake_time() - dt))
        };
        self.tips = trial.tips;
        self.pose = trial.pose;
        self.step = trial.step;
        self.margins = trial.margins;
        self.clearance = trial.clearance;
        self.tracker = trial.tracker;
        self.end_tracker = trial.end_tracker;
        self.path_low = trial.path_low;
        self.mid_tracker = trial.mid_tracker;
        self.velocity = v;
    }

    /// Moves the setpoint by the candidate velocities over `dt`, reduced if
    /// needed (`checked`: the candidate is a command; otherwise it is the
    /// controlled stop, taken as it is); returns the limit held at.
    pub(super) fn advance(
        &mut self,
        dt: T,
        candidate: &Velocities<T>,
        checked: bool,
    ) -> Option<HoldAt> {
        let miss = match self.trial(dt, candidate, checked) {
            Ok(trial) => {
                self.commit(dt, trial, *candidate);
                self.widened = None;
                return None;
            }
            Err(miss) => miss,
        };
        let reason = miss.at;
        let brake = self.brake(dt);
        let mut best = None;
        if checked {
            // First only what the limit belongs to (one module's tip and
            // the view, which moves both modules' joints), then everything.
            // When the cycle before held at the same limit and its own
            // parts did not suffice, everything is reduced at once.
            let all = [true; 3];
            let own = culprits(&reason);
            let widened = self.widened == Some(reason);
            if !widened {
                best = self.search(dt, &brake, candidate, own, miss);
            }
            if best.is_none() && own != all {
                best = self.search(dt, &brake, candidate, all, miss);
                self.widened = best.is_some().then_some(reason);
            } else {
                self.widened = None;
            }
            if widened && best.is_none() {
                best = self.search(dt, &brake, candidate, own, miss);
            }
        }
        let (trial, v) = match best {
            Some(found) => found,
            None => match self.trial(dt, &brake, false) {
                Ok(trial) => (trial, brake),
                Err(Miss {
                    at: HoldAt::Reach(e),
                    ..
                }) => {
                    // Not even the stop solves: hold the setpoint as it is.
                    self.velocity = Velocities::zero();
                    self.enter_fault(Fault::Unsolvable(e));
                    return Some(HoldAt::Reach(e));
                }
                Err(other) => return Some(other.at),
            },
        };
        self.commit(dt, trial, v);
        Some(reason)
    }
}

#[cfg(test)]
mod tests {
    use super::dip;

    #[test]
    fn the_dip_is_a_quadratics_minimum() {
        // f(s) = 2 (s - 0.3)^2 + 0.05: its minimum 0.05 at s = 0.3, between
        // the samples 0.23, 0.13 and 1.03.
        let f = |s: f64| 2.0 * (s - 0.3) * (s - 0.3) + 0.05;
        assert!((dip(f(0.0), f(0.5), f(1.0)) - 0.05).abs() < 1e-15);
        // Its minimum outside [0, 1], or a concave one: the lowest sample.
        let g = |s: f64| (1.0 - s) * (1.0 - s) - 0.5 * s;
        assert_eq!(dip(g(0.0), g(0.5), g(1.0)), g(1.0));
        assert_eq!(dip(0.0, 1.0, 0.5), 0.0);
    }
}
