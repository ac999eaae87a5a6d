#!/usr/bin/env bash
# Every test: sets up, then runs all suites through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"
