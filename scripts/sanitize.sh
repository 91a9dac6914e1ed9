#!/usr/bin/env bash
# The torch-free layers (core, mpm, io, data) and their tests, built with AddressSanitizer and
# UndefinedBehaviorSanitizer in build-asan/ and run with ctest: any report (an out-of-bounds
# access, a use after free, a leak, undefined behaviour) fails the test that made it. The tests
# that run the `nsf` tool, and the torch layers, are left out (CMake: NSF_WITH_TORCH=OFF).
# Usage: bash scripts/sanitize.sh [ctest arguments]    NSF_JOBS: build jobs (default: all cores)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
bash scripts/install-deps.sh
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# -O1: fast enough for the simulation tests; no -g, to keep the build short (reports name the
# functions; add -g1 to CMAKE_CXX_FLAGS for lines). Not Release: assert() and Eigen's own
# assertions stay on.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1" -DCMAKE_C_FLAGS="-O1" \
  -DNSF_SANITIZE=ON -DNSF_WITH_TORCH=OFF -DNSF_NATIVE=OFF -DNSF_BUILD_BENCH=OFF -DNSF_HWCAPS=OFF \
  "${launcher[@]}" >/dev/null
# Set before the build: the build runs the test binary to list its tests.
supp="$PWD/scripts/sanitize.supp"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$supp"
export LSAN_OPTIONS="suppressions=$supp:print_suppressions=0"
cmake --build build-asan -j"${NSF_JOBS:-$(nproc)}"
built=$(date +%s)
ctest --test-dir build-asan --output-on-failure --timeout 900 "$@"
end=$(date +%s)
echo "sanitize: clean; build $((built - start)) s, tests $((end - built)) s, $(date -u +%F) on $(nproc) cores"
