//! Runs one input through one target's check, outside libFuzzer, to look
//! into a finding: `cargo run --manifest-path fuzz/Cargo.toml --example
//! replay -- TARGET FILE` (the panic, if any, says what failed).

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [name, path] = args.as_slice() else {
        eprintln!("usage: replay TARGET FILE");
        return ExitCode::from(2);
    };
    let Some((_, check)) = parasils_fuzz::TARGETS.iter().find(|(n, _)| n == name) else {
        let names: Vec<&str> = parasils_fuzz::TARGETS.iter().map(|(n, _)| *n).collect();
        eprintln!("no target {name}: one of {names:?}");
        return ExitCode::from(2);
    };
    let data = match std::fs::read(path) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("cannot read {path}: {e}");
            return ExitCode::from(2);
        }
    };
    check(&data);
    println!("{name}: {path} passes");
    ExitCode::SUCCESS
}
