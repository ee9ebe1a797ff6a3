//! libFuzzer's entry for the `calibration_data` target; the check is
//! `parasils_fuzz::calibration::calibration_data`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::calibration::calibration_data(data));
