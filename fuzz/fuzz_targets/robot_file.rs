//! libFuzzer's entry for the `robot_file` target; the check is
//! `parasils_fuzz::robot_file::robot_file`, which the corpus replay test runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::robot_file::robot_file(data));
