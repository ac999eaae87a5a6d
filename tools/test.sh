#!/usr/bin/env bash
# Every test: sets up, runs all suites through CTest in the optimized build (the soak included),
# then again under the sanitizers with the fuzzers (tools/sanitize.sh). docs/reliability.md says
# what runs where and for how long.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
# Tests render sound to memory; none of them may reach for a sound card.
export ALSOFT_DRIVERS="${ALSOFT_DRIVERS:-null}"
ctest --test-dir build --output-on-failure -j"$(nproc)"
tools/sanitize.sh
