//! The margin supervisor: warnings, and stops demanded before a margin runs
//! out.
//!
//! Every cycle of [`Controller::step`](crate::kin::Controller::step) reports
//! how far the robot is from each of its hard limits: the instrument modules'
//! singularities (`|cos qs2|`, `qs3`) and joint limits, module 1's serial and
//! parallel singularities and actuator strokes. The solvers refuse a pose
//! beyond a hard threshold with an error, which in a running loop is too
//! late: the platform is moving and needs distance to stop. A [`Supervisor`]
//! watches the same margins ([`Margins`], one value per [`Margin`]) against
//! two thresholds of its own, each above the hard one:
//!
//! - a **warning** threshold: a margin below it is reported (a
//!   [`MarginSet`] of warnings), and nothing else happens;
//! - a **stop** threshold, between the warning and the hard one: a margin
//!   that would end below it if a controlled stop began now demands that
//!   stop.
//!
//! "Would end below it" is a first-order prediction: a controlled stop
//! decelerates every axis uniformly to rest in `T_stop` (see
//! [`OnlineMulti::stop`](crate::traj::OnlineMulti::stop)), covering half the
//! distance it would at constant velocity, so a margin `m` changing at the
//! rate `m'` ends near `m + m' T_stop / 2`. A stop is demanded for a margin
//! that decreases (`m' < 0`) and whose predicted end is below the stop
//! threshold ([`Supervisor::check_ahead`]); a margin that is low but
//! growing, as when the platform leaves a singularity it was stopped near,
//! demands nothing. [`OnlineController`](crate::OnlineController) runs
//! this check every cycle with the rates from the previous cycle's margins
//! and carries the stop out; [`Supervisor::check`] is the static test
//! (`m` below the stop threshold), for a loop that knows no rates.
//!
//! # Default thresholds
//! [`Supervisor::default`], for the default hard thresholds (see
//! `docs/model.md`, *Singularities and thresholds*):
//!
//! | margin | unit | hard | stop | warning |
//! |---|---|---|---|---|
//! | `|cos qs2|`, each instrument module | - | `1e-6` | `0.05` | `0.1` |
//! | `qs3`, each instrument module | mm | `1e-6` | `2` | `5` |
//! | `qs1`, `qs2` to their limits, each module | rad | `0` | `1 deg` | `5 deg` |
//! | `qs3` to its limits, each module | mm | `0` | `2` | `10` |
//! | module 1's smallest serial margin | - | `1e-6` | `0.05` | `0.1` |
//! | module 1's parallel margin | - | `1e-2` | `0.03` | `0.1` |
//! | module 1's actuators to their stroke ends | mm | `0` | `2` | `10` |
//!
//! The parallel margin's stop and warning are 3 and 10 times the hard
//! threshold (`ParallelThresholds::parallel_command`); the dimensionless
//! singularity margins stop where joint rates are amplified about 20 times
//! (`1 / 0.05`) and warn at 10 times. Along the paper's reorientation the
//! smallest margins are 0.53 (parallel), 0.73 (serial), 0.47 (`|cos qs2|`),
//! 18 deg (`qs2` to its limit) and about 50 mm (strokes): no warning.
//!
//! ```
//! use parasils::kin::{Controller, MarginTracker, PlatformState, Pose, TipTargets};
//! use parasils::supervisor::{Margin, Margins, Supervisor};
//!
//! let controller = Controller::<f64>::paper();
//! let at_rest = PlatformState::at_rest(Pose::paper_start());
//! let step = controller.step(&at_rest, &TipTargets::paper(), &mut MarginTracker::new())?;
//! let margins = Margins::of(&step);
//! assert!(margins[Margin::Parallel] > 0.7);
//! let verdict = Supervisor::default().check(&margins);
//! assert!(verdict.warnings.is_empty() && verdict.stop.is_empty());
//! # Ok::<(), parasils::kin::Error>(())
//! ```

use core::ops::{Index, IndexMut};

use crate::Real;
use crate::error::Error;
use crate::kin::{ClearancePair, ControlStep, Controller};
pub use crate::margin::Margin;

/// One value per [`Margin`] (each in its unit): the margins of a cycle, their
/// rates of change, or a set of thresholds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Margins<T>(pub [T; Margin::COUNT]);

impl<T: Real> Margins<T> {
    /// Every value `x`.
    pub fn splat(x: T) -> Self {
        Self([x; Margin::COUNT])
    }

    /// The margins of one control cycle.
    pub fn of(step: &ControlStep<T>) -> Self {
        let mut m = Self::splat(T::zero());
        for (side, s) in [(0, &step.left), (4, &step.right)] {
            let v = [
                s.margins.cos_qs2,
                s.margins.qs3,
                min(s.margins.limits.qs1, s.margins.limits.qs2),
                s.margins.limits.qs3,
            ];
            for (k, x) in v.into_iter().enumerate() {
                if let Some(slot) = m.0.get_mut(side + k) {
                    *slot = x;
                }
            }
        }
        let m1 = &step.module1.margins;
        m[Margin::Serial] = m1.serial_min;
        m[Margin::Parallel] = m1.parallel;
        m[Margin::Stroke] = m1.stroke.iter().fold(m1.stroke[0], |a, &b| min(a, b));
        m
    }

    /// The smallest values a controller's solvers accept (a margin below is
    /// an error of [`Controller::step`]): the instrument modules' singularity
    /// thresholds, module 1's serial threshold and command parallel
    /// threshold, and 0 for the distances to limits and stroke ends.
    pub fn hard(controller: &Controller<T>) -> Self {
        let mut m = Self::splat(T::zero());
        let (l, r) = (
            &controller.left.geometry().thresholds,
            &controller.right.geometry().thresholds,
        );
        m[Margin::LeftCosQs2] = l.cos_qs2;
        m[Margin::LeftQs3] = l.qs3;
        m[Margin::RightCosQs2] = r.cos_qs2;
        m[Margin::RightQs3] = r.qs3;
        let th = &controller.module1.geometry().thresholds;
        m[Margin::Serial] = th.serial;
        m[Margin::Parallel] = th.parallel_command;
        m
    }
}

impl<T> Index<Margin> for Margins<T> {
    type Output = T;
    fn index(&self, m: Margin) -> &T {
        // The array has exactly one slot per margin: the index is in bounds.
        &self.0[m.index()]
    }
}

impl<T> IndexMut<Margin> for Margins<T> {
    fn index_mut(&mut self, m: Margin) -> &mut T {
        &mut self.0[m.index()]
    }
}

/// A set of [`Margin`]s, one bit each: the margins below their warning
/// thresholds, or those that demand a stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct MarginSet(u16);

impl MarginSet {
    /// No margin.
    pub const EMPTY: Self = Self(0);

    /// The set with these bits (bit `k` is the margin of index `k`; bits
    /// beyond [`Margin::COUNT`] are dropped).
    pub const fn from_bits(bits: u16) -> Self {
        Self(bits & ((1 << Margin::COUNT) - 1))
    }

    /// Bit `k` set for the margin of index `k`.
    pub const fn bits(self) -> u16 {
        self.0
    }

    /// Whether the set holds no margin.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether `m` is in the set.
    pub const fn contains(self, m: Margin) -> bool {
        self.0 & (1 << m as u16) != 0
    }

    /// Adds `m`.
    pub fn insert(&mut self, m: Margin) {
        self.0 |= 1 << m as u16;
    }

    /// The margins of both sets.
    #[must_use]
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// How many margins the set holds.
    pub const fn len(self) -> u32 {
        self.0.count_ones()
    }

    /// The margins in the set, in index order.
    pub fn iter(self) -> impl Iterator<Item = Margin> {
        Margin::ALL.into_iter().filter(move |m| self.contains(*m))
    }

    /// The first margin in the set (in index order), if any.
    pub fn first(self) -> Option<Margin> {
        self.iter().next()
    }
}

/// The supervisor's verdict on one cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Verdict {
    /// The margins below their warning thresholds.
    pub warnings: MarginSet,
    /// The margins that demand a controlled stop; empty when none does.
    pub stop: MarginSet,
}

/// Warning and stop thresholds for every [`Margin`] (see the
/// [module docs](self)); plain data, checked against a controller's hard
/// thresholds by [`Supervisor::validate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Supervisor<T> {
    /// A margin below its value here is reported as a warning.
    pub warn: Margins<T>,
    /// A decreasing margin predicted to end below its value here if a stop
    /// began now demands that stop.
    pub stop: Margins<T>,
}

impl<T: Real> Default for Supervisor<T> {
    /// The thresholds of the [module docs](self)' table.
    fn default() -> Self {
        let lit = |x: f64| T::lit(x);
        let deg = |x: f64| lit(x.to_radians());
        let side = |cos: f64, qs3: f64, angle: T, qs3_limits: f64| {
            [lit(cos), lit(qs3), angle, lit(qs3_limits)]
        };
        let build = |s: [T; 4], module1: [f64; 3]| {
            let mut m = Margins::splat(T::zero());
            for (k, x) in s.into_iter().chain(s).enumerate() {
                if let Some(slot) = m.0.get_mut(k) {
                    *slot = x;
                }
            }
            m[Margin::Serial] = lit(module1[0]);
            m[Margin::Parallel] = lit(module1[1]);
            m[Margin::Stroke] = lit(module1[2]);
            m
        };
        Self {
            warn: build(side(0.1, 5.0, deg(5.0), 10.0), [0.1, 0.1, 10.0]),
            stop: build(side(0.05, 2.0, deg(1.0), 2.0), [0.05, 0.03, 2.0]),
        }
    }
}

impl<T: Real> Supervisor<T> {
    /// Checks the thresholds against the smallest values `hard` the
    /// solvers accept ([`Margins::hard`]): every threshold finite, each stop
    /// threshold above the hard one, each warning threshold at least the stop
    /// one.
    ///
    /// # Errors
    /// [`Error::InvalidThreshold`] naming the first threshold that is not.
    pub fn validate(&self, hard: &Margins<T>) -> Result<(), Error> {
        for m in Margin::ALL {
            let (stop, warn) = (self.stop[m], self.warn[m]);
            if !(stop > hard[m] && stop.finite()) {
                return Err(Error::InvalidThreshold {
                    what: "stop",
                    margin: m,
                    value: stop.to_f64(),
                    min: hard[m].to_f64(),
                });
            }
            if !(warn >= stop && warn.finite()) {
                return Err(Error::InvalidThreshold {
                    what: "warning",
                    margin: m,
                    value: warn.to_f64(),
                    min: stop.to_f64(),
                });
            }
        }
        Ok(())
    }

    /// The static verdict on margins `now`: warnings below the warning
    /// thresholds, a stop for each margin below its stop threshold (a NaN
    /// margin is below every threshold).
    pub fn check(&self, now: &Margins<T>) -> Verdict {
        let mut v = Verdict::default();
        for m in Margin::ALL {
            if !(now[m] >= self.warn[m]) {
                v.warnings.insert(m);
            }
            if !(now[m] >= self.stop[m]) {
                v.stop.insert(m);
            }
        }
        v
    }

    /// The verdict on a moving robot: warnings as [`check`](Self::check); a
    /// stop for each margin that decreases (`rates`, per s, negative) and
    /// would end below its stop threshold if a controlled stop of
    /// `stop_time` (s) began now, predicted as `now + rate stop_time / 2`
    /// (see the [module docs](self)). A NaN margin or rate demands a stop.
    pub fn check_ahead(&self, now: &Margins<T>, rates: &Margins<T>, stop_time: T) -> Verdict {
        let mut v = Verdict::default();
        let half = stop_time * T::lit(0.5);
        for m in Margin::ALL {
            let (x, rate) = (now[m], rates[m]);
            if !(x >= self.warn[m]) {
                v.warnings.insert(m);
            }
            if heads_below(x, rate, half, self.stop[m]) {
                v.stop.insert(m);
            }
        }
        v
    }
}

/// Whether a value `x` changing at `rate` (per s) demands a stop: it
/// decreases and `x + rate lead` is below `stop` (a NaN value or rate
/// demands one): [`Supervisor::check_ahead`]'s prediction.
fn heads_below<T: Real>(x: T, rate: T, lead: T, stop: T) -> bool {
    let decreasing = !(rate >= T::zero());
    decreasing && !(x + rate * lead >= stop)
}

/// A set of [`ClearancePair`]s, one bit each: the gaps below their warning
/// threshold, or those that demand a stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PairSet(u8);

impl PairSet {
    /// No pair.
    pub const EMPTY: Self = Self(0);

    const fn bit(pair: ClearancePair) -> u8 {
        match pair {
            ClearancePair::LeftRight => 1,
            ClearancePair::LeftEndoscope => 2,
            ClearancePair::RightEndoscope => 4,
        }
    }

    /// Whether the set holds no pair.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether `pair` is in the set.
    pub const fn contains(self, pair: ClearancePair) -> bool {
        self.0 & Self::bit(pair) != 0
    }

    /// Adds `pair`.
    pub fn insert(&mut self, pair: ClearancePair) {
        self.0 |= Self::bit(pair);
    }

    /// How many pairs the set holds.
    pub const fn len(self) -> u32 {
        self.0.count_ones()
    }

    /// The pairs in the set, in the order of [`ClearancePair::ALL`].
    pub fn iter(self) -> impl Iterator<Item = ClearancePair> {
        ClearancePair::ALL
            .into_iter()
            .filter(move |p| self.contains(*p))
    }

    /// The first pair in the set (in the order of [`ClearancePair::ALL`]).
    pub fn first(self) -> Option<ClearancePair> {
        self.iter().next()
    }
}

/// The supervisor's verdict on the three clearance gaps of one cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ClearanceVerdict {
    /// The pairs whose gap is below the warning threshold.
    pub warnings: PairSet,
    /// The pairs whose gap demands a controlled stop; empty when none does.
    pub stop: PairSet,
}

/// Warning and stop thresholds on the surface gaps between the bodies
/// (mm; [`parasils_kin::Clearance`], in the order of
/// [`ClearancePair::ALL`]): the same for the three pairs. A gap may be
/// negative (the bodies overlap), so no hard threshold bounds these from
/// below; the robot file's `[supervisor]` keys `clearance_warn_mm` and
/// `clearance_stop_mm` (assumed defaults 2.0 and 0.5 mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceThresholds<T> {
    /// A gap below this is reported as a warning, mm.
    pub warn: T,
    /// A decreasing gap predicted to end below this demands a stop, mm.
    pub stop: T,
}

impl<T: Real> ClearanceThresholds<T> {
    /// Both thresholds finite, the warning at least the stop one.
    ///
    /// # Errors
    /// [`Error::InvalidClearanceThreshold`] naming the first that is not.
    pub fn validate(&self) -> Result<(), Error> {
        if !self.stop.finite() {
            return Err(Error::InvalidClearanceThreshold {
                what: "stop",
                value: self.stop.to_f64(),
                min: f64::NEG_INFINITY,
            });
        }
        if !(self.warn >= self.stop && self.warn.finite()) {
            return Err(Error::InvalidClearanceThreshold {
                what: "warning",
                value: self.warn.to_f64(),
                min: self.stop.to_f64(),
            });
        }
        Ok(())
    }

    /// The verdict on the gaps `now` (mm) of a moving robot, changing at
    /// `rates` (mm/s) with the second derivatives `bends` (mm/s^2, each
    /// gap's along the path at the current speed, see
    /// [`OnlineController`](crate::OnlineController)): a warning for each
    /// gap below the warning threshold, and a stop for each that decreases
    /// and would end below the stop threshold if the controlled stop began
    /// at the next cycle, `period` (s) from now.
    ///
    /// The prediction is the margins' ([`Supervisor::check_ahead`]) with
    /// two terms more, because a gap's stop threshold is a line the bodies
    /// must not cross, not a margin to a harder limit:
    ///
    /// - **a lead of cycles**: the stop that begins at the next cycle lasts
    ///   at most `stop_time + period` (the speed grows by one cycle of
    ///   acceleration at most) and covers half the way it would at
    ///   constant speed, and the rate is measured over the last cycle (it
    ///   is the rate of half a cycle ago), so the gap is predicted to move
    ///   by `rate L` with `L = 1.5 period + (stop_time + period) / 2`; the
    ///   check runs once per cycle, so a stop demanded at the first cycle
    ///   whose prediction for a stop *now* crosses the threshold would end
    ///   below it by up to a cycle's change;
    /// - **the bend**: a gap is not linear along the path (two shafts
    ///   closing in close faster and faster); along the stop's straight
    ///   line it ends near `now + rate L + bend L^2 / 2`, the bend counted
    ///   only when it brings the end lower (`bend < 0`);
    /// - **an allowance** of 25 % on the predicted fall, for what a
    ///   second-order prediction leaves out (the bend's own change over
    ///   the stop, a new command's change of acceleration during the cycle
    ///   before the stop, the path's turn when the two angles are time
    ///   synchronised): stops end up to that much earlier, never later, as
    ///   the 10^5 random retarget sequences of `tests/online_clearance.rs`
    ///   check (with 10 %, one of them ended 2e-6 mm below).
    ///
    /// A NaN gap, rate or bend demands a stop.
    pub fn check_ahead(
        &self,
        now: &[T; 3],
        rates: &[T; 3],
        bends: &[T; 3],
        stop_time: T,
        period: T,
    ) -> ClearanceVerdict {
        let mut v = ClearanceVerdict::default();
        for (((pair, x), rate), bend) in ClearancePair::ALL
            .into_iter()
            .zip(*now)
            .zip(*rates)
            .zip(*bends)
        {
            let one = self.check_gap_ahead(x, rate, bend, stop_time, period);
            if one.warning {
                v.warnings.insert(pair);
            }
            if one.stop {
                v.stop.insert(pair);
            }
        }
        v
    }

    /// The verdict on one gap `now` (mm) changing at `rate` (mm/s) with
    /// the bend `bend` (mm/s^2): the prediction of
    /// [`check_ahead`](Self::check_ahead) for a single gap (what the online
    /// controller applies to the smallest gap to the forbidden regions).
    /// A NaN gap, rate or bend demands a stop.
    pub fn check_gap_ahead(&self, now: T, rate: T, bend: T, stop_time: T, period: T) -> GapVerdict {
        let half = T::lit(0.5);
        let lead = period * T::lit(1.5) + (stop_time + period) * half;
        let lower = if bend < T::zero() {
            bend * lead * lead * half
        } else if bend >= T::zero() {
            T::zero()
        } else {
            bend
        };
        // The predicted change, negative when the gap falls.
        let change = (rate * lead + lower) * T::lit(1.25);
        let decreasing = !(rate >= T::zero()) || bend.is_nan() || now.is_nan();
        GapVerdict {
            warning: !(now >= self.warn),
            stop: decreasing && !(now + change >= self.stop),
        }
    }
}

/// The supervisor's verdict on one gap
/// ([`ClearanceThresholds::check_gap_ahead`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GapVerdict {
    /// The gap is below the warning threshold.
    pub warning: bool,
    /// The gap demands a controlled stop.
    pub stop: bool,
}

fn min<T: Real>(a: T, b: T) -> T {
    if b < a { b } else { a }
}
