//! libFuzzer's entry for the `csv` target; the check is
//! `parasils_fuzz::writers::csv`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::writers::csv(data));
