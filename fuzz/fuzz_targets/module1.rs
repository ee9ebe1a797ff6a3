//! libFuzzer's entry for the `module1` target; the check is
//! `parasils_fuzz::kin::module1`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::kin::module1(data));
