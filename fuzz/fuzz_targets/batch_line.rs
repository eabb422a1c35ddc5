#![no_main]
//! Invariant: see `dalembert::fuzzing::batch_line` (written above that function).
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    dalembert::fuzzing::batch_line(data);
});
