//! libFuzzer's entry for the `mcap` target; the check is
//! `parasils_fuzz::writers::mcap`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::writers::mcap(data));
