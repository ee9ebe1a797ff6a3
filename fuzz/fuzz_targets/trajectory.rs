//! libFuzzer's entry for the `trajectory` target; the check is
//! `parasils_fuzz::traj::trajectory`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::traj::trajectory(data));
