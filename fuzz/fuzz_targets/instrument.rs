//! libFuzzer's entry for the `instrument` target; the check is
//! `parasils_fuzz::kin::instrument`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::kin::instrument(data));
