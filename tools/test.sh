#!/usr/bin/env bash
# Every test: sets up, then runs all suites through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
# Tests render sound to memory; none of them may reach for a sound card.
export ALSOFT_DRIVERS="${ALSOFT_DRIVERS:-null}"
ctest --test-dir build --output-on-failure -j"$(nproc)"
