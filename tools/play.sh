#!/usr/bin/env bash
# The main job: sets up, then simulates the air hockey table with two scripted mallets.
# Extra arguments go to `quantum simulate` (see build/quantum simulate --help).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
build/quantum simulate rules/airhockey --events build/events.jsonl --snapshot build/snapshot.png "$@"
