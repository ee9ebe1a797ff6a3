//! Limits held, never an error: a cycle's candidate motion is checked at
//! the setpoint it reaches and at the point where the robot would come to
//! rest if it braked from there; a candidate that would cross a limit is
//! reduced, by bisection between the controlled stop and the candidate, to
//! the largest fraction that passes (see `docs/model.md`, *Teleoperation*).

use crate::kin::nalgebra::Vector3;
use crate::kin::{
    Bodies, Clearance, ClearancePair, ControlStep, MarginTracker, ModuleCommand, PlatformState,
    Pose, Real, TipMotion, TipTargets,
};
use crate::supervisor::{Margin, Margins};

use super::core::{Teleop, Velocities};
use super::cycle::{Fault, HoldAt};

/// How many halvings the search for the largest admissible fraction takes
/// (the fraction to within 1/64 of the cycle's change of velocity).
const BISECTIONS: usize = 6;

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
        HoldAt::Clearance(_) | HoldAt::Reach(_) => [true; 3],
    }
}

/// The three gaps of `c`, in the order of [`ClearancePair::ALL`], mm.
fn gap_array<T: Real>(c: &Clearance<T>) -> [T; 3] {
    ClearancePair::ALL.map(|pair| c.get(pair).gap)
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

/// A candidate cycle solved.
struct Trial<T: Real> {
    tips: [Vector3<T>; 2],
    pose: Pose<T>,
    step: ControlStep<T>,
    margins: Margins<T>,
    clearance: Option<Clearance<T>>,
    tracker: MarginTracker<T>,
    end_tracker: MarginTracker<T>,
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
    fn admissible(&self, m: &Margins<T>, gaps: Option<[T; 3]>) -> Result<(), HoldAt> {
        for k in Margin::ALL {
            if !(m[k] >= self.supervisor.stop[k]) && !(m[k] >= self.margins[k]) {
                return Err(HoldAt::Margin(k));
            }
        }
        if let (Some((_, th)), Some(gaps), Some(now)) = (&self.watch, gaps, &self.clearance) {
            for (pair, g) in ClearancePair::ALL.into_iter().zip(gaps) {
                if !(g >= th.stop) && !(g >= now.get(pair).gap) {
                    return Err(HoldAt::Clearance(pair));
                }
            }
        }
        Ok(())
    }

    /// The cycle reached with the velocities `v` over `dt`, solved; with
    /// `check`, it and its stopping point must be admissible.
    fn trial(&self, dt: T, v: &Velocities<T>, check: bool) -> Result<Trial<T>, HoldAt> {
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
        let step = self
            .controller
            .step_commanded(&platform, &command(0), &command(1), &mut tracker)
            .map_err(HoldAt::Reach)?;
        let margins = Margins::of(&step);
        let clearance = self.clearance_of(&step).map_err(HoldAt::Reach)?;
        let mut end_tracker = self.end_tracker;
        if check {
            let gaps = clearance.as_ref().map(gap_array);
            self.admissible(&margins, gaps)?;
            if !v.is_zero() {
                // The controlled stop from this setpoint keeps to the line
                // from it to `x + v (T_stop / 2 + dt)` (one cycle late):
                // solved at its middle and its end, and each margin and gap
                // checked there and at the lowest point of the parabola
                // through its three values (a dip between the points).
                let reach = self.stop_time(v) * T::lit(0.5) + dt;
                let mut along = [(margins, gaps); 3];
                for (i, s) in [(1, T::lit(0.5)), (2, T::one())] {
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
                            &mut end_tracker,
                        )
                        .map_err(HoldAt::Reach)?;
                    let g = self.clearance_of(&end).map_err(HoldAt::Reach)?;
                    along[i] = (Margins::of(&end), g.as_ref().map(gap_array));
                    self.admissible(&along[i].0, along[i].1)?;
                }
                let mut lowest = margins;
                for (k, x) in lowest.0.iter_mut().enumerate() {
                    *x = dip(along[0].0.0[k], along[1].0.0[k], along[2].0.0[k]);
                }
                let gaps = match (along[0].1, along[1].1, along[2].1) {
                    // Zipped, not indexed: no bounds check is left to panic.
                    (Some(mut a), Some(b), Some(c)) => {
                        for ((x, y), z) in a.iter_mut().zip(b).zip(c) {
                            *x = dip(*x, y, z);
                        }
                        Some(a)
                    }
                    _ => None,
                };
                self.admissible(&lowest, gaps)?;
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
        })
    }

    /// The largest fraction `s` (to `2^-BISECTIONS`) of the way from the
    /// stop `brake` to `candidate` in the parts `which` that passes.
    fn search(
        &self,
        dt: T,
        brake: &Velocities<T>,
        candidate: &Velocities<T>,
        which: [bool; 3],
    ) -> Option<(Trial<T>, Velocities<T>)> {
        let mut best = None;
        let (mut lo, mut hi) = (T::zero(), T::one());
        for _ in 0..BISECTIONS {
            let mid = (lo + hi) * T::lit(0.5);
            let v = brake.lerp(candidate, mid, which);
            match self.trial(dt, &v, true) {
                Ok(trial) => {
                    lo = mid;
                    best = Some((trial, v));
                }
                Err(_) => hi = mid,
            }
        }
        if best.is_none() && which != [true; 3] {
            // The stop in these parts alone, the rest as commanded.
            let v = brake.lerp(candidate, T::zero(), which);
            if let Ok(trial) = self.trial(dt, &v, true) {
                best = Some((trial, v));
            }
        }
        best
    }

    fn commit(&mut self, trial: Trial<T>, v: Velocities<T>) {
        self.tips = trial.tips;
        self.pose = trial.pose;
        self.step = trial.step;
        self.margins = trial.margins;
        self.clearance = trial.clearance;
        self.tracker = trial.tracker;
        self.end_tracker = trial.end_tracker;
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
        let reason = match self.trial(dt, candidate, checked) {
            Ok(trial) => {
                self.commit(trial, *candidate);
                return None;
            }
            Err(reason) => reason,
        };
        let brake = self.brake(dt);
        let mut best = None;
        if checked {
            // First only what the limit belongs to (one module's tip and
            // the view, which moves both modules' joints), then everything.
            let all = [true; 3];
            let own = culprits(&reason);
            best = self.search(dt, &brake, candidate, own);
            if best.is_none() && own != all {
                best = self.search(dt, &brake, candidate, all);
            }
        }
        let (trial, v) = match best {
            Some(found) => found,
            None => match self.trial(dt, &brake, false) {
                Ok(trial) => (trial, brake),
                Err(HoldAt::Reach(e)) => {
                    // Not even the stop solves: hold the setpoint as it is.
                    self.velocity = Velocities::zero();
                    self.enter_fault(Fault::Unsolvable(e));
                    return Some(HoldAt::Reach(e));
                }
                Err(other) => return Some(other),
            },
        };
        self.commit(trial, v);
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
