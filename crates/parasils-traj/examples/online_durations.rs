//! Durations of online profiles, one problem per line: the parasils side of
//! `benches/python/ruckig_compare.py`.
//!
//! Each line of standard input is one problem in f64, comma-separated:
//! `p0,v0,target,v_max,a_max` for one axis, or ten fields (the same for
//! axis 0, then for axis 1) for two axes, time-synchronised. Blank lines and
//! lines starting with `#` are skipped. Each problem gives one line on
//! standard output: the duration in s (shortest representation that reads
//! back to the same f64), then for two axes the synchronisation used and each
//! axis's own minimum time; or `error: ` and the reason.
//!
//! `printf '0,0,10,2,1\n' | cargo run -p parasils-traj --example online_durations`
//! prints `7.0`.

use std::io::{BufRead, BufWriter, Write};

use parasils_traj::{Limits, OnlineMulti, OnlineTrapezoid, State, Synchronization};

/// One axis: start state, target and limits.
fn axis(f: &[f64]) -> (State<f64>, f64, Limits<f64>) {
    let start = State {
        position: f[0],
        velocity: f[1],
        acceleration: 0.0,
    };
    (start, f[2], Limits::new(f[3], f[4]))
}

/// The output line for one input line.
fn solve(line: &str) -> Result<String, String> {
    let fields: Vec<f64> = line
        .split(',')
        .map(|x| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}")))
        .collect::<Result<_, _>>()?;
    match fields.len() {
        5 => {
            let (s, g, l) = axis(&fields);
            let p = OnlineTrapezoid::new(s, g, l).map_err(|e| e.to_string())?;
            Ok(format!("{:?}", p.duration()))
        }
        10 => {
            let (s0, g0, l0) = axis(&fields[..5]);
            let (s1, g1, l1) = axis(&fields[5..]);
            let m = OnlineMulti::new([s0, s1], [g0, g1], [l0, l1], Synchronization::Time)
                .map_err(|e| e.to_string())?;
            let own0 = OnlineTrapezoid::new(s0, g0, l0).map_err(|e| e.to_string())?;
            let own1 = OnlineTrapezoid::new(s1, g1, l1).map_err(|e| e.to_string())?;
            let sync = match m.synchronization() {
                Synchronization::Phase => "phase",
                Synchronization::Time => "time",
                Synchronization::None => "none",
            };
            Ok(format!(
                "{:?},{sync},{:?},{:?}",
                m.duration(),
                own0.duration(),
                own1.duration()
            ))
        }
        n => Err(format!(
            "{n} fields: expected 5 (one axis) or 10 (two axes)"
        )),
    }
}

fn main() -> std::io::Result<()> {
    let stdin = std::io::stdin();
    let mut out = BufWriter::new(std::io::stdout().lock());
    for line in stdin.lock().lines() {
        let line = line?;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        match solve(line) {
            Ok(s) => writeln!(out, "{s}")?,
            Err(e) => writeln!(out, "error: {e}")?,
        }
    }
    out.flush()
}
