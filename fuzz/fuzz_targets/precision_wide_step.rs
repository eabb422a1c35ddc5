#![no_main]
//! Invariant: see `dalembert::fuzzing::precision_wide_step` (written above that function).
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    dalembert::fuzzing::precision_wide_step(data);
});
