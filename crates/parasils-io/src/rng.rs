//! A small seeded random generator (SplitMix64) for the calibration's pose
//! planner, the tolerance study's perturbed robots and the synthetic data of
//! tests and benchmarks: the same seed gives the same numbers on every
//! platform and with every dependency version.

/// SplitMix64: 64 bits of state, every seed valid.
#[derive(Debug, Clone)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// The generator of `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`, 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Standard normal (Box-Muller).
    pub fn normal(&mut self) -> f64 {
        // 1 - unit() is in (0, 1]: the logarithm is finite.
        let r = (-2.0 * (1.0 - self.unit()).ln()).sqrt();
        r * (core::f64::consts::TAU * self.unit()).cos()
    }

    /// An index in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.unit() * n as f64) as usize).min(n.saturating_sub(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_of_the_normal_and_the_uniform() {
        let mut rng = Rng::new(7);
        let n = 200_000;
        let (mut s1, mut s2, mut u1) = (0.0, 0.0, 0.0);
        for _ in 0..n {
            let x = rng.normal();
            s1 += x;
            s2 += x * x;
            u1 += rng.unit();
        }
        let n = f64::from(n);
        // Standard errors: 1/sqrt(n) = 0.0022 for the mean, 0.0032 for the
        // variance, 0.00065 for the uniform's mean.
        assert!((s1 / n).abs() < 0.01, "{}", s1 / n);
        assert!((s2 / n - 1.0).abs() < 0.015, "{}", s2 / n);
        assert!((u1 / n - 0.5).abs() < 0.003, "{}", u1 / n);
    }
}
