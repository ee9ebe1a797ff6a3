//! A reach map as CSV: one row per cell, `dtheta` rows outer, `dpsi` inner.

use std::io::Write;

use crate::map::ReachMap;

/// The columns, in order.
pub const HEADER: [&str; 9] = [
    "dpsi_deg",
    "dtheta_deg",
    "psi_deg",
    "theta_deg",
    "feasible",
    "reachable",
    "line",
    "limiting",
    "margin",
];

/// Writes `map` to `out` as CSV: the [`HEADER`], then one row per cell:
/// the increments and the angles (the start's as the user gave them plus
/// the increment), deg; the flags as 0 or 1 (`line` empty when the lines
/// were not computed); the limiting constraint's code; the normalised
/// margin.
///
/// # Errors
/// The writer's.
pub fn write<W: Write>(map: &ReachMap, out: &mut W) -> std::io::Result<()> {
    let mut buf = ryu::Buffer::new();
    writeln!(out, "{}", HEADER.join(","))?;
    let [psi0, theta0] = map.start_deg;
    let flag = |b: bool| if b { "1" } else { "0" };
    for (i, cell) in map.cells.iter().enumerate() {
        let [dpsi, dtheta] = map.increments_deg(i);
        for v in [dpsi, dtheta, psi0 + dpsi, theta0 + dtheta] {
            out.write_all(buf.format(v).as_bytes())?;
            out.write_all(b",")?;
        }
        let line = cell.line.map_or("", flag);
        write!(
            out,
            "{},{},{},{},",
            flag(cell.feasible),
            flag(cell.reachable),
            line,
            map.code(cell.limiting)
        )?;
        out.write_all(buf.format(cell.margin).as_bytes())?;
        out.write_all(b"\n")?;
    }
    out.flush()
}
