//! Text output to the host over semihosting, without `core::fmt`.
//!
//! `core::fmt` formats floats through `flt2dec`, whose assertions are panic
//! paths that the optimiser cannot remove; since this firmware links with a
//! panic handler that must never be referenced (see `main.rs`), it prints
//! through this small writer instead: strings, integers and fixed-point
//! decimals, every index checked by `get`, nothing that can panic.

use cortex_m_semihosting::hio::{self, HostStream};

/// A line-buffered writer to the host's stdout.
pub struct Out {
    stream: Option<HostStream>,
    buf: [u8; 160],
    len: usize,
}

impl Out {
    /// Opens the host's stdout (output is dropped if the host refuses).
    pub fn new() -> Self {
        Self {
            stream: hio::hstdout().ok(),
            buf: [0; 160],
            len: 0,
        }
    }

    /// Sends the buffered bytes to the host.
    pub fn flush(&mut self) {
        if let (Some(stream), Some(bytes)) = (self.stream.as_mut(), self.buf.get(..self.len)) {
            let _ = stream.write_all(bytes);
        }
        self.len = 0;
    }

    fn byte(&mut self, b: u8) {
        if self.len >= self.buf.len() {
            self.flush();
        }
        if let Some(slot) = self.buf.get_mut(self.len) {
            *slot = b;
            self.len += 1;
        }
    }

    /// Writes `s`.
    pub fn str(&mut self, s: &str) -> &mut Self {
        for b in s.bytes() {
            self.byte(b);
        }
        self
    }

    /// Ends the line and flushes it.
    pub fn nl(&mut self) {
        self.byte(b'\n');
        self.flush();
    }

    /// Writes `n` in decimal.
    pub fn u64(&mut self, mut n: u64) -> &mut Self {
        let mut digits = [0u8; 20];
        let mut used = 0;
        for slot in digits.iter_mut() {
            *slot = b'0' + (n % 10) as u8;
            n /= 10;
            used += 1;
            if n == 0 {
                break;
            }
        }
        for &d in digits.iter().take(used).rev() {
            self.byte(d);
        }
        self
    }

    /// Writes `x` with `decimals` digits after the point (at most 9), rounded;
    /// `nan` or `inf` for those, and `>1e12` beyond.
    pub fn fixed(&mut self, x: f64, decimals: u32) -> &mut Self {
        if x.is_nan() {
            return self.str("nan");
        }
        if x < 0.0 {
            self.byte(b'-');
        }
        let a = if x < 0.0 { -x } else { x };
        if a == f64::INFINITY {
            return self.str("inf");
        }
        if a >= 1e12 {
            return self.str(">1e12");
        }
        let decimals = if decimals > 9 { 9 } else { decimals };
        let scale = 10u64.pow(decimals);
        // `as` saturates and never panics; a < 1e12 and scale <= 1e9 fit u64.
        let scaled = (a * scale as f64 + 0.5) as u64;
        let (whole, frac) = match (scaled.checked_div(scale), scaled.checked_rem(scale)) {
            (Some(w), Some(f)) => (w, f),
            _ => (scaled, 0),
        };
        self.u64(whole);
        if decimals > 0 {
            self.byte(b'.');
            let mut div = scale;
            for _ in 0..decimals {
                div /= 10;
                let d = (frac / div.max(1)).checked_rem(10).unwrap_or_default();
                self.byte(b'0' + d as u8);
            }
        }
        self
    }
}
