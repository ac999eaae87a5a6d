#!/usr/bin/env bash
# The main job: sets up, then plays a short Quantum air hockey match between two simulated
# players (the sport in rules/airhockey). Extra arguments go to `quantum play`.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
build/quantum play rules/airhockey --seconds 60 --events build/events.jsonl "$@"
