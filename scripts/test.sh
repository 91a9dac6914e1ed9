#!/usr/bin/env bash
# The test command: sets up (packages, build) and runs the whole test suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
# Each test runs with 2 OpenMP threads (set in CMake); run tests one at a time so they don't fight.
ctest --test-dir build --output-on-failure --timeout 600 "$@"
