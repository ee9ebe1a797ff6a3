//! What the online controller watches besides the margins: the gaps
//! between the bodies ([`ClearanceWatch`]) and to the forbidden regions,
//! each with its rate and bend from the previous ticks ([`GapTrack`]).

use crate::Real;
use crate::kin::BodyGeometry;
use crate::kin::Clearance;
use crate::supervisor::ClearanceThresholds;
use crate::traj::State;

/// How far above the clearance stop threshold (mm) a command looks its
/// motion's first cycle ahead even when no gap is below the warning
/// threshold (see [`OnlineController::command`]).
///
/// [`OnlineController::command`]: crate::OnlineController::command
pub const PROBE_BAND_MM: f64 = 1.0;

/// What the online controller needs to watch the clearance between the
/// instrument shafts and the endoscope, and to the forbidden regions
/// ([`OnlineController::with_clearance`]).
///
/// [`OnlineController::with_clearance`]: crate::OnlineController::with_clearance
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceWatch<T> {
    /// The bodies' sizes, mm.
    pub bodies: BodyGeometry<T>,
    /// The endoscope's insertion below `P` along `-Z'`, mm.
    pub endoscope_depth: T,
    /// The warning and stop thresholds on every gap, mm (the pairs' and
    /// the forbidden regions').
    pub thresholds: ClearanceThresholds<T>,
}

/// `N` gaps as the ticks saw them: the latest, their rates and their bends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GapTrack<T, const N: usize> {
    /// The previous tick's gaps, mm.
    pub(super) previous: Option<[T; N]>,
    /// Their rates from the tick before, mm/s (`None` before two ticks).
    pub(super) rates: Option<[T; N]>,
    /// Their second derivatives along the path at the current speed,
    /// mm/s^2 (0 before three ticks).
    pub(super) bends: [T; N],
}

impl<T: Real, const N: usize> GapTrack<T, N> {
    /// Nothing seen yet.
    pub(super) fn new() -> Self {
        Self {
            previous: None,
            rates: None,
            bends: [T::zero(); N],
        }
    }

    /// The rates to check now (0 before two ticks).
    pub(super) fn rates_or_zero(&self) -> [T; N] {
        self.rates.unwrap_or([T::zero(); N])
    }

    /// Takes this tick's gaps `now`; `per_s` is 1 / the interval since the
    /// previous tick (1/s), `None` at the first tick or a repeated instant.
    pub(super) fn observe(&mut self, now: &[T; N], per_s: Option<T>, angles: &[State<T>; 2]) {
        if let (Some(per_s), Some(before)) = (per_s, self.previous) {
            self.update(now, &before, per_s, angles);
        }
        self.previous = Some(*now);
    }

    /// The rates from the gaps `now` and `before`, one cycle apart
    /// (`per_s` = 1 / the cycle, 1/s), and the bends from the change of the
    /// rates: a gap `g(t) = G(sigma(t))`, `sigma` the way travelled in
    /// `(psi, theta)`, has `g'' = G'' sigma'^2 + G' sigma''`; the bend is
    /// `G'' sigma'^2 = g'' - g' sigma'' / sigma'`, what `g''` would be at
    /// the current speed `sigma'` held constant (the motion's own
    /// acceleration `sigma''` taken out), 0 at rest.
    fn update(&mut self, now: &[T; N], before: &[T; N], per_s: T, angles: &[State<T>; 2]) {
        let [a, b] = angles;
        let speed = (a.velocity * a.velocity + b.velocity * b.velocity).sqrt();
        let along = if speed > T::zero() {
            (a.velocity * a.acceleration + b.velocity * b.acceleration) / (speed * speed)
        } else {
            T::zero()
        };
        let mut rates = [T::zero(); N];
        for ((r, g), p) in rates.iter_mut().zip(now).zip(before) {
            *r = (*g - *p) * per_s;
        }
        if let Some(old) = self.rates {
            for ((bend, r), o) in self.bends.iter_mut().zip(rates).zip(old) {
                *bend = if speed > T::zero() {
                    (r - o) * per_s - r * along
                } else {
                    T::zero()
                };
            }
        }
        self.rates = Some(rates);
    }
}

/// The clearance watched, and what the previous ticks saw of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Watched<T> {
    pub(super) watch: ClearanceWatch<T>,
    /// The three gaps between the bodies.
    pub(super) pairs: GapTrack<T, 3>,
    /// The smallest gap of each in-body part, `[left, right, endoscope]`,
    /// to the forbidden regions (reset by a tick without regions or while
    /// the part is not inside).
    pub(super) regions: [GapTrack<T, 1>; 3],
    /// The latest interval between two ticks, s.
    pub(super) period: Option<T>,
    /// A command's time and the rates its motion starts with, looked ahead
    /// (see [`OnlineController::command`]): the tick at that time checks
    /// them instead of the rates of the motion before.
    ///
    /// [`OnlineController::command`]: crate::OnlineController::command
    pub(super) probe: Option<(T, [T; 3])>,
}

/// The three gaps of `c` in the order of [`ClearancePair::ALL`], mm.
///
/// [`ClearancePair::ALL`]: crate::kin::ClearancePair::ALL
pub(super) fn gap_array<T: Real>(c: &Clearance<T>) -> [T; 3] {
    [
        c.left_right.gap,
        c.left_endoscope.gap,
        c.right_endoscope.gap,
    ]
}
