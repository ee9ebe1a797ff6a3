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

/// The columns a map with a stiffness measure adds after [`HEADER`]: how
/// far each tip gives way under the map's load, mm
/// ([`Cell::deflection_mm`](crate::Cell::deflection_mm); empty on an
/// infeasible cell).
pub const DEFLECTION: [&str; 2] = ["left_tip_deflection_mm", "right_tip_deflection_mm"];

/// Writes `map` to `out` as CSV: the [`HEADER`], then one row per cell:
/// the increments and the angles (the start's as the user gave them plus
/// the increment), deg; the flags as 0 or 1 (`line` empty when the lines
/// were not computed); the limiting constraint's code; the normalised
/// margin; with a stiffness measure, the [`DEFLECTION`] columns.
///
/// # Errors
/// The writer's.
pub fn write<W: Write>(map: &ReachMap, out: &mut W) -> std::io::Result<()> {
    let mut buf = ryu::Buffer::new();
    let deflection = map.options.deflection_load_n.is_some();
    write!(out, "{}", HEADER.join(","))?;
    if deflection {
        write!(out, ",{}", DEFLECTION.join(","))?;
    }
    writeln!(out)?;
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
        if deflection {
            for d in cell.deflection_mm.map_or([None; 2], |d| d.map(Some)) {
                out.write_all(b",")?;
                if let Some(d) = d {
                    out.write_all(buf.format(d).as_bytes())?;
                }
            }
        }
        out.write_all(b"\n")?;
    }
    out.flush()
}
