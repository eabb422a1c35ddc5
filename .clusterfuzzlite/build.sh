#!/bin/bash -eu
# ClusterFuzzLite (and OSS-Fuzz) build: every cargo-fuzz target of fuzz/Cargo.toml, copied to
# $OUT with its committed corpus as seed corpus. Runs from the repository root (the image's
# WORKDIR). Locally, without a sanitizer toolchain:
#   SANITIZER=none OUT=/tmp/cflite-out .clusterfuzzlite/build.sh
# tests/clusterfuzzlite.rs checks that TARGETS is exactly the [[bin]] list of fuzz/Cargo.toml.
TARGETS=(newton_step retraction batch_line scenes_step scene_file precision_step precision_wide_step)

# inari needs AVX2/FMA (haswell, not native: the binaries may run on other runners than the
# one that built them). cargo-fuzz sets RUSTFLAGS itself, which hides the flag of
# .cargo/config.toml: give it here, after whatever the build environment set.
export RUSTFLAGS="${RUSTFLAGS:-} -Ctarget-cpu=haswell"
flags=()
if [ "${SANITIZER:-address}" = none ]; then
    flags=(-s none)
fi

cd fuzz
cargo fuzz build -O ${flags[@]+"${flags[@]}"}
bins="${CARGO_TARGET_DIR:-target}/x86_64-unknown-linux-gnu/release"
mkdir -p "$OUT"
for target in "${TARGETS[@]}"; do
    cp "$bins/$target" "$OUT/"
    if [ -d "corpus/$target" ]; then
        rm -f "$OUT/${target}_seed_corpus.zip"
        (cd "corpus/$target" && zip -q -r "$OUT/${target}_seed_corpus.zip" .)
    fi
done
