#!/usr/bin/env bash
# The Python wheel: one abi3 manylinux2014 wheel that carries the extension
# twice, built for any x86-64 (`_geopid`) and for x86-64-v3 (AVX2, FMA:
# `_geopid_x86_64_v3`); `geopid` imports the second on a CPU that has those
# features. The SIMD lanes choose their instructions when compiled (the lane
# Monte Carlo runs 2.6x faster with AVX2), so a wheel that travels needs
# both builds; RUSTFLAGS replaces the workspace's `target-cpu=native`, which
# must never reach a wheel.
#
#   scripts/build-wheel.sh [OUT_DIR]      (default target/wheels; also writes the sdist)
#
# Needs maturin and ziglang (pip): zig links against glibc 2.17's symbols.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/wheels}
common=(--release --zig --compatibility manylinux2014 -m python/Cargo.toml)
v3_so=python/geopid/_geopid_x86_64_v3.abi3.so
tmp=$(mktemp -d)
trap 'rm -rf "$tmp" "$v3_so"' EXIT

# Separate target directories: with different RUSTFLAGS, one would rebuild
# the other's artefacts each time.
CARGO_TARGET_DIR=target/wheel-x86-64-v3 RUSTFLAGS="-C target-cpu=x86-64-v3" \
    python3 -m maturin build "${common[@]}" --features x86-64-v3 --out "$tmp"
python3 -c 'import sys, zipfile; sys.stdout.buffer.write(zipfile.ZipFile(sys.argv[1]).read("geopid/_geopid.abi3.so"))' "$tmp"/geopid-*.whl > "$v3_so"
test -s "$v3_so"

# The baseline build; maturin packs every file of python/geopid, the
# x86-64-v3 module beside it included.
CARGO_TARGET_DIR=target/wheel-baseline RUSTFLAGS="-C target-cpu=x86-64" \
    python3 -m maturin build "${common[@]}" --out "$out"
rm -f "$v3_so"
python3 -m maturin sdist -m python/Cargo.toml --out "$out"
