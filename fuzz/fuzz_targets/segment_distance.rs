//! libFuzzer's entry for the `segment_distance` target; the check is
//! `parasils_fuzz::clearance::segment_distance`, which the corpus replay
//! test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::clearance::segment_distance(data));
