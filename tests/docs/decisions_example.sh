#!/usr/bin/env bash
# docs/decisions.md's worked example, as a reader runs it: a seeded match of shooting practice
# (every third goal earns the goal seeker) with a handicap, both logs written, and their audit.
# Run by CTest (docs_decisions_example); the argument is the quantum binary (build/quantum).
set -euo pipefail
quantum="${1:-build/quantum}"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
cd "$(dirname "$0")/../.."
"$quantum" play rules/practice --seconds 120 --seed 3 --handicap 2 --audio none --quiet \
  --decisions "$dir/decisions.jsonl" --events "$dir/events.jsonl"
"$quantum" audit "$dir/decisions.jsonl" "$dir/events.jsonl"
