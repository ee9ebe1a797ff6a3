//! One control cycle of the online controller: the follow law when it is
//! on, the kinematics, the gaps, the supervisor's verdict.

use super::controller::OnlineController;
use super::setpoint::{MotionKind, Setpoint};
use super::watch::{GapTrack, gap_array};
use crate::Real;
use crate::error::Error;
use crate::follow::Follow;
use crate::regions::{
    ForbiddenRegions, InBodyCapsules, NearestRegion, NoRegions, RegionQueryError,
};
use crate::supervisor::{GapVerdict, Margins};
use crate::traj::{OnlineMulti, State, Synchronization};

impl<T: Real> OnlineController<T> {
    /// One control cycle at `t` (s) without forbidden regions:
    /// [`tick_with`](Self::tick_with)`(t, &NoRegions)`.
    ///
    /// # Errors
    /// As [`tick_with`](Self::tick_with).
    pub fn tick(&mut self, t: T) -> Result<Setpoint<T>, Error> {
        self.tick_with(t, &NoRegions)
    }

    /// One control cycle at `t` (s): while the camera follows the tips, the
    /// follow law's cycle (its recentring, when it plans one, becomes the
    /// active motion); the platform state of the active motion at `t`; the
    /// kinematics for it with the tips as set; the gaps between the bodies
    /// and, with `regions` not empty, the smallest gap from the in-body
    /// parts to them; and the supervisor's verdict on the margins and the
    /// gaps (a demanded stop is carried out from this cycle's state; see
    /// the [module docs](crate::online)).
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`], [`Error::TimeReversed`];
    /// [`Error::Follow`] when the follow law cannot take the cycle (the
    /// midpoint cannot be looked at); [`Error::Kinematics`] when the state
    /// cannot be solved; [`Error::NoClearanceWatch`] for regions without
    /// the bodies' sizes ([`with_clearance`](Self::with_clearance));
    /// [`Error::Region`] when a region's gap cannot be computed (or is
    /// NaN). The controller is then unchanged.
    pub fn tick_with(
        &mut self,
        t: T,
        regions: &dyn ForbiddenRegions<T>,
    ) -> Result<Setpoint<T>, Error> {
        self.check_time(t)?;
        let with_regions = !regions.is_empty();
        if with_regions && self.clearance.is_none() {
            return Err(Error::NoClearanceWatch);
        }
        // The follow law's cycle, kept apart until the cycle succeeds (a
        // copy only while the camera follows: the law is large, and a tick
        // without it copies none).
        let mut law: Option<Follow<T>> = None;
        let mut adopted: Option<(OnlineMulti<T, 2>, T)> = None;
        let angles = match &self.follow {
            Some(following) => {
                let law = law.insert(*following);
                let step = law.step(t, &[self.tips.left, self.tips.right])?;
                if step.replanned
                    && let Some((profile, start)) = law.recentring()
                {
                    adopted = Some((*profile, start));
                } else if law.recentring().is_none() {
                    let held = step.angles.map(|a| a.position);
                    if self.goal() != held || !self.is_at_rest(t) {
                        // The recentring ended: the motion rests where the
                        // law holds.
                        let rest = OnlineMulti::new(
                            held.map(State::rest),
                            held,
                            self.limits,
                            Synchronization::Phase,
                        )?;
                        adopted = Some((rest, t));
                    }
                }
                step.angles
            }
            None => self.angles_at(t),
        };
        let state = self.platform(angles);
        let mut tracker = self.tracker;
        // The step stays in its `Result` until it goes into the setpoint:
        // one move of it instead of two.
        let solved = self.solve(&state, &mut tracker);
        let step = match &solved {
            Ok(step) => step,
            Err(e) => return Err((*e).into()),
        };
        let margins = Margins::of(step);
        let (clearance, each) = match &self.clearance {
            Some(w) => {
                let bodies = self.bodies(&w.watch, step)?;
                let each = if with_regions {
                    nearest_each(
                        regions,
                        &InBodyCapsules::of(
                            &bodies,
                            step.left.q.qs3,
                            step.right.q.qs3,
                            w.watch.endoscope_depth,
                        ),
                    )?
                } else {
                    [None; 3]
                };
                (Some(bodies.clearance()?), each)
            }
            None => (None, [None; 3]),
        };
        let nearest = each
            .into_iter()
            .flatten()
            .reduce(|a, b| if b.gap_mm < a.gap_mm { b } else { a });
        let mut period = T::zero();
        let mut per_s = None;
        if let Some((t_prev, m_prev)) = self.previous
            && t > t_prev
        {
            period = t - t_prev;
            let inverse = T::one() / period;
            per_s = Some(inverse);
            for ((r, m), p) in self.rates.0.iter_mut().zip(margins.0).zip(m_prev.0) {
                *r = (m - p) * inverse;
            }
        }
        if let (Some(w), Some(c)) = (&mut self.clearance, &clearance) {
            w.pairs.observe(&gap_array(c), per_s, &angles);
            if per_s.is_some() {
                w.period = Some(period);
            }
            for (track, n) in w.regions.iter_mut().zip(&each) {
                match n {
                    Some(n) => track.observe(&[n.gap_mm], per_s, &angles),
                    None => *track = GapTrack::new(),
                }
            }
        }
        self.tracker = tracker;
        self.previous = Some((t, margins));
        self.last = Some(t);
        if let Some((motion, start)) = adopted {
            self.motion = motion;
            self.start = start;
        }
        if law.is_some() {
            self.follow = law;
        }
        let stop_time = self.stop_time(&angles);
        let verdict = self
            .supervisor
            .check_ahead(&margins, &self.rates, stop_time);
        let (gap_verdict, region_verdict) = match (&mut self.clearance, &clearance) {
            (Some(w), Some(c)) => {
                // At a command's own tick, the rates its motion starts with.
                let rates = match w.probe {
                    Some((t0, rates)) if t0 == t => rates,
                    _ => w.pairs.rates_or_zero(),
                };
                w.probe = None;
                let pairs = w.watch.thresholds.check_ahead(
                    &gap_array(c),
                    &rates,
                    &w.pairs.bends,
                    stop_time,
                    period,
                );
                let mut region = GapVerdict::default();
                for (track, n) in w.regions.iter().zip(&each) {
                    if let Some(n) = n {
                        let one = w.watch.thresholds.check_gap_ahead(
                            n.gap_mm,
                            track.rates_or_zero()[0],
                            track.bends[0],
                            stop_time,
                            period,
                        );
                        region.warning |= one.warning;
                        region.stop |= one.stop;
                    }
                }
                (pairs, region)
            }
            _ => Default::default(),
        };
        // What the setpoint reports of the motion, before a stop demanded
        // below begins; the setpoint itself is built last, in place.
        let (command, kind, follow) = (self.command_index(), self.kind, self.follow_phase());
        // A gap's demand at a motion's first instant, still at rest, holds
        // the platform there (a stop of zero duration): the motion would
        // take it below the stop threshold.
        let gap_stop = !gap_verdict.stop.is_empty() || region_verdict.stop;
        let holds = gap_stop && !self.is_at_rest(t);
        if (!verdict.stop.is_empty() || gap_stop)
            && !self.kind.is_stop()
            && (stop_time > T::zero() || holds)
            && let Ok(motion) = OnlineMulti::stop(angles, self.limits)
        {
            self.begin(t, motion, MotionKind::SupervisorStop);
        }
        solved.map_err(Error::from).map(|step| Setpoint {
            t,
            state,
            step,
            tips: self.tips,
            command,
            kind,
            follow,
            margins,
            warnings: verdict.warnings,
            stop: verdict.stop,
            clearance,
            clearance_warnings: gap_verdict.warnings,
            clearance_stop: gap_verdict.stop,
            region: nearest,
            region_warning: region_verdict.warning,
            region_stop: region_verdict.stop,
        })
    }
}

/// The smallest gap from each in-body part of `inside` to `regions`,
/// `[left, right, endoscope]` (`None` for a part not inside, or when no
/// region answers): one query per part, so that each part's gap has its
/// own rate (the smallest over the parts has kinks where the nearest part
/// changes, and a rate measured across one would lag). A NaN or `-inf` gap
/// is the region's error.
fn nearest_each<T: Real>(
    regions: &dyn ForbiddenRegions<T>,
    inside: &InBodyCapsules<T>,
) -> Result<[Option<NearestRegion<T>>; 3], Error> {
    let none = InBodyCapsules {
        left: None,
        right: None,
        endoscope: None,
    };
    let parts = [
        InBodyCapsules {
            left: inside.left,
            ..none
        },
        InBodyCapsules {
            right: inside.right,
            ..none
        },
        InBodyCapsules {
            endoscope: inside.endoscope,
            ..none
        },
    ];
    let mut each = [None; 3];
    for (out, (part, capsule)) in each.iter_mut().zip(parts.iter().zip(inside.all())) {
        if capsule.is_none() {
            continue;
        }
        let n = regions.nearest(part)?;
        if let Some(n) = n
            && !(n.gap_mm.finite() || n.gap_mm > T::zero())
        {
            return Err(RegionQueryError { region: n.region }.into());
        }
        *out = n;
    }
    Ok(each)
}
