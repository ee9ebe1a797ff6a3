//! What the procedure tests share: a procedure's text planned, or the
//! message that refuses it.

use std::path::Path;

use parasils_sim::{Simulation, procedure};

/// The procedure `text` (files it names read from `base`) read and planned.
pub fn simulate_text(text: &str, base: &Path) -> Result<Simulation, Box<dyn core::error::Error>> {
    let scenario = procedure::parse(text, "test", base)?;
    Ok(Simulation::new(scenario)?)
}

/// Why the procedure `text` is refused, when read or when planned:
/// `"accepted"` when it is not.
pub fn refusal(text: &str) -> String {
    match procedure::parse(text, "test", Path::new(".")) {
        Err(e) => e.to_string(),
        Ok(scenario) => match Simulation::new(scenario) {
            Err(e) => e.to_string(),
            Ok(_) => String::from("accepted"),
        },
    }
}
