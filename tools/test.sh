#!/usr/bin/env bash
# Every test: sets up, runs all suites through CTest in the optimized build (the soak included),
# then again under the sanitizers with the fuzzers (tools/sanitize.sh). docs/reliability.md says
# what runs where and for how long.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
# Tests render sound to memory; none of them may reach for a sound card.
export ALSOFT_DRIVERS="${ALSOFT_DRIVERS:-null}"
# A test that hangs fails by name after 10 minutes (the longest takes 2 here, 4 under the
# sanitizers) instead of running into CI's limit; the soak sets its own.
ctest --test-dir build --output-on-failure --timeout 600 -j"$(nproc)"
tools/sanitize.sh
