//! libFuzzer's entry for the `cli_simulate` target; the check is
//! `parasils_fuzz::cli::cli_simulate`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::cli::cli_simulate(data));
