#!/usr/bin/env bash
# Every test, once: sets up, runs in the optimized build the tests whose cost is repetition
# (labels statistical, long and soak: hundreds of seeded matches, the full-size tables, the
# soak's hour), then every other test under the sanitizers with the fuzzers and a shorter soak
# (tools/sanitize.sh). docs/reliability.md says what runs where, why, and for how long.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
# Tests render sound to memory; none of them may reach for a sound card.
export ALSOFT_DRIVERS="${ALSOFT_DRIVERS:-null}"
# A test that hangs fails by name after 10 minutes (the longest takes 2 here, 4 under the
# sanitizers) instead of running into CI's limit; the soak sets its own.
ctest --test-dir build --output-on-failure --timeout 600 -j"$(nproc)" -L 'statistical|long|soak'
tools/sanitize.sh -LE 'statistical|long'
