//! libFuzzer's entry for the `procedure_file` target; the check is
//! `parasils_fuzz::procedure::procedure_file`, which the corpus replay test
//! runs too.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| parasils_fuzz::procedure::procedure_file(data));
