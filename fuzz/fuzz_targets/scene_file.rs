#![no_main]
//! Invariant: see `dalembert::fuzzing::scene_file` (written above that function).
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    dalembert::fuzzing::scene_file(data);
});
