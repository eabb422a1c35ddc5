#![no_main]
//! Invariant: see `dalembert::fuzzing::scenes_step` (written above that function).
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    dalembert::fuzzing::scenes_step(data);
});
