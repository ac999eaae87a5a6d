#!/usr/bin/env bash
# The main job: sets up what a match needs (the engine's packages and the quantum program, not
# the tests), then plays a short Quantum air hockey match between two simulated players (the
# sport in rules/airhockey). Extra arguments go to `quantum play`.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh --play quantum
build/quantum play airhockey --seconds 60 --events build/events.jsonl "$@"
