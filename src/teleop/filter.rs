//! The input mapping's shaping: the dead zone of a normalised axis, and the
//! low-pass filter against tremor (a critically damped second-order
//! filter, see `docs/model.md`, *Teleoperation*).

use crate::kin::Real;

/// The dead zone of a normalised axis `x` (in `[-1, 1]`): 0 within
/// `dead_zone` of 0, then rising linearly from 0 to 1 at full scale, so the
/// command is continuous at the zone's edge; the result is clamped to
/// `[-1, 1]`.
pub fn dead_zone<T: Real>(x: T, dead_zone: T) -> T {
    let m = x.abs();
    if !(m > dead_zone) {
        return T::zero();
    }
    let y = ((m - dead_zone) / (T::one() - dead_zone)).min(T::one());
    if x < T::zero() { -y } else { y }
}

/// A critically damped second-order low-pass filter of `N` components.
///
/// The filter is `x'' = w^2 (u - x) - 2 w x'`, two real poles at
/// `-w = -2 pi f_c`, the transfer function `H(s) = w^2 / (s + w)^2`:
///
/// ```text
/// |H(j 2 pi f)| = 1 / (1 + (f / f_c)^2)        tau(f) = 2 w / (w^2 + (2 pi f)^2)
/// ```
///
/// (`tau` the group delay, `2 / w` at low frequencies). With the assumed
/// `f_c = 2.5 Hz` it passes a surgeon's deliberate motion (below about 1
/// Hz: -1.3 dB at 1 Hz) and attenuates the physiological tremor band, 6 to
/// 16 Hz, by 16.6 dB at 6 Hz to 32.5 dB at 16 Hz; its lag is 127 ms at low
/// frequencies (110 ms at 1 Hz). A step of the input never overshoots
/// (critical damping), so a full-scale step never asks the tip for more
/// than the full-scale speed. It is stepped exactly for an input held over
/// the cycle (the zero-order hold), so it is stable and the same filter
/// whatever the period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowPass<T, const N: usize> {
    /// `w = 2 pi f_c`, rad/s.
    omega: T,
    /// The output.
    x: [T; N],
    /// The output's rate, per s.
    v: [T; N],
}

impl<T: Real, const N: usize> LowPass<T, N> {
    /// At rest at 0, its poles at `cutoff_hz` (Hz, positive).
    pub fn new(cutoff_hz: T) -> Self {
        Self {
            omega: T::two_pi() * cutoff_hz,
            x: [T::zero(); N],
            v: [T::zero(); N],
        }
    }

    /// The output.
    pub fn output(&self) -> [T; N] {
        self.x
    }

    /// The output's rate of change, per s.
    pub fn rate(&self) -> [T; N] {
        self.v
    }

    /// Back to rest at 0.
    pub fn reset(&mut self) {
        self.x = [T::zero(); N];
        self.v = [T::zero(); N];
    }

    /// At rest at `x`: the output `x`, its rate 0.
    pub fn hold_at(&mut self, x: [T; N]) {
        self.x = x;
        self.v = [T::zero(); N];
    }

    /// Steps the filter by `dt` (s) with the input `u` held over it; returns
    /// the output.
    pub fn update(&mut self, dt: T, u: [T; N]) -> [T; N] {
        let w = self.omega;
        let decay = (-w * dt).exp();
        for ((x, v), u) in self.x.iter_mut().zip(self.v.iter_mut()).zip(u) {
            let e0 = *x - u;
            let b = *v + w * e0;
            *x = u + (e0 + b * dt) * decay;
            *v = (*v - w * b * dt) * decay;
        }
        self.x
    }

    /// The gain `|H|` at `f_hz` (Hz) of the filter with its poles at
    /// `cutoff_hz`.
    pub fn gain(cutoff_hz: T, f_hz: T) -> T {
        let r = f_hz / cutoff_hz;
        T::one() / (T::one() + r * r)
    }

    /// The group delay at `f_hz` (s) of the filter with its poles at
    /// `cutoff_hz`.
    pub fn group_delay(cutoff_hz: T, f_hz: T) -> T {
        let w = T::two_pi() * cutoff_hz;
        let o = T::two_pi() * f_hz;
        (w + w) / (w * w + o * o)
    }
}
