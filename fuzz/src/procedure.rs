//! The procedure file parser with arbitrary text, as TOML
//! (`parasils_sim::procedure::parse`) or as JSON of the same structure
//! (`parse_json`, what the Python bindings send): no call may panic; an
//! error has a message; an accepted procedure has motions, and plans into a
//! simulation (or a typed error) whose first records are finite.
//!
//! A procedure may name a robot file, which the parser reads: inputs that do
//! (a top-level `robot` key, however the text spells it) are left out, so
//! that the fuzzer never reads a file of its choosing (`/dev/zero` would
//! never end). The robot file parser has a target of its own.

use std::path::Path;

use parasils_sim::{Simulation, procedure};

/// Whether `text` (TOML or JSON) has a top-level `robot` key.
fn names_a_robot(text: &str, json: bool) -> bool {
    if json {
        serde_json::from_str::<serde_json::Value>(text)
            .is_ok_and(|v| v.as_object().is_some_and(|o| o.contains_key("robot")))
    } else {
        text.parse::<toml::Table>()
            .is_ok_and(|t| t.contains_key("robot"))
    }
}

/// The target's check: the first byte picks TOML (even) or JSON (odd).
pub fn procedure_file(data: &[u8]) {
    let (json, rest) = match data.split_first() {
        Some((&b, rest)) => (b & 1 == 1, rest),
        None => (false, data),
    };
    let text = String::from_utf8_lossy(rest);
    if names_a_robot(&text, json) {
        return;
    }
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../procedures");
    let parsed = if json {
        procedure::parse_json(&text, &base)
    } else {
        procedure::parse(&text, "procedure file", &base)
    };
    let scenario = match parsed {
        Ok(s) => s,
        Err(e) => {
            assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
            return;
        }
    };
    assert!(
        scenario.is_procedure() && !scenario.motions().is_empty(),
        "a procedure without motions"
    );
    let sim = match Simulation::new(scenario) {
        Ok(sim) => sim,
        Err(e) => {
            assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
            return;
        }
    };
    let d = sim.duration();
    assert!(d.is_finite() && d >= 0.0, "a planned duration of {d} s");
    assert!(sim.sample_count() >= 1, "no sample");
    for (k, record) in sim.samples().take(3).enumerate() {
        match record {
            Ok(r) => {
                assert_eq!(r.index, k);
                let row = parasils_sim::columns::csv_row(&r);
                assert!(
                    row.iter().all(|v| v.is_finite()),
                    "a non-finite record {r:?}"
                );
            }
            Err(e) => {
                assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
                break;
            }
        }
    }
}
