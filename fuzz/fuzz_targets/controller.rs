//! libFuzzer's entry for the `controller` target; the check is
//! `parasils_fuzz::kin::controller`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::kin::controller(data));
