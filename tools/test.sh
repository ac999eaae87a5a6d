#!/usr/bin/env bash
# Every test: sets up, runs in the optimized build the tests whose cost is repetition (labels
# statistical, long and soak: hundreds of seeded matches, the full-size tables, the soak's hour),
# those that assert its CPU bound per frame (label bounds: the sandbox and hostile scripts; label
# faults: kills, outputs, recordings and reloads under faults) and
# the install and the Debian package of what a venue gets (label install), the seeded logs kept
# byte for byte, which are this build's floating point (label golden), then every other
# test under the sanitizers with the fuzzers and a shorter soak (tools/sanitize.sh). docs/reliability.md says what runs where, why, and for how long.
set -euo pipefail
cd "$(dirname "$0")/.."
# The optimized build makes what its tests run (the installed programs among them); the
# sanitizer build makes every target.
tools/setup.sh quantum quantum_tests quantum-soak quantum-synth quantum-bench
# Tests render sound to memory; none of them may reach for a sound card.
export ALSOFT_DRIVERS="${ALSOFT_DRIVERS:-null}"
# A test that hangs fails by name after 10 minutes (the longest takes 2 here, 4 under the
# sanitizers) instead of running into CI's limit; the soak sets its own.
ctest --test-dir build --output-on-failure --timeout 600 -j"$(nproc)" -L 'statistical|long|soak|bounds|faults|install|golden'
# Each fuzz target's share of the run (tools/sanitize.sh alone gives each 60 s): seven targets at 20 s
# take what five took at 30.
QUANTUM_FUZZ_SECONDS="${QUANTUM_FUZZ_SECONDS:-20}" tools/sanitize.sh -LE 'statistical|long|install|golden'
