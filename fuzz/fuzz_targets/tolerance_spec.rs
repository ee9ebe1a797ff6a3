//! libFuzzer's entry for the `tolerance_spec` target; the check is
//! `parasils_fuzz::calibration::tolerance_spec`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::calibration::tolerance_spec(data));
