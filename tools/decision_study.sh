#!/usr/bin/env bash
# Plays MATCHES seeded matches of SPORT (seeds 1..MATCHES, SECONDS each, as fast as they go),
# keeps their decision and event logs in DIR, and audits them all pooled (docs/decisions.md).
# Further arguments go to every `quantum play`, e.g. --auto-balance 0.5.
#   tools/decision_study.sh rules/airhockey 700 600 /tmp/walls
set -euo pipefail
if (($# < 4)); then
  echo "usage: tools/decision_study.sh SPORT MATCHES SECONDS DIR [PLAY OPTIONS...]" >&2
  exit 1
fi
sport="$1" matches="$2" seconds="$3" dir="$4"
shift 4
quantum="$(cd "$(dirname "$0")/.." && pwd)/build/quantum"
mkdir -p "$dir"
logs=()
for ((seed = 1; seed <= matches; ++seed)); do
  "$quantum" play "$sport" --seed "$seed" --seconds "$seconds" --audio none --quiet --pace fast \
    --decisions "$dir/decisions-$seed.jsonl" --events "$dir/events-$seed.jsonl" "$@"
  logs+=("$dir/decisions-$seed.jsonl" "$dir/events-$seed.jsonl")
done
exec "$quantum" audit "${logs[@]}"
