#!/usr/bin/env bash
# The engine installed as a venue installs it (docs/install.md): `cmake --install` into a fresh
# prefix, then, from an unrelated folder with a clean environment, the sports listed, one played
# by name, a designer's sport from a QUANTUM_PATH folder played and its spec run, a misspelt
# name answered with the nearest; and nothing installed names the build or the source folder.
# Run by CTest (install_anywhere); arguments: the build folder, the source folder, cmake.
set -euo pipefail
build="$(realpath "$1")"
source="$(realpath "$2")"
cmake="${3:-cmake}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
fail() { echo "install test: $*" >&2; exit 1; }

"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log" || { cat "$work/install.log"; fail "cmake --install failed"; }
for f in bin/quantum bin/quantum-synth share/quantum/rules/lib/two_teams.lua share/quantum/rules/powerups/penalty.lua \
         share/quantum/rules/spec_helpers.lua share/quantum/rules/handball/sport.lua share/quantum/sounds/goal.wav \
         share/quantum/markers/markers.pdf share/doc/quantum/README.md; do
  [ -e "$prefix/$f" ] || fail "$f was not installed"
done
# A path compiled into a program or written into a file would tie the install to this machine.
if grep -rlaF -e "$source" -e "$build" "$prefix"; then fail "the files above name the source or build folder"; fi

# A clean environment: only what the sanitizer build needs to report (tools/sanitize.sh).
clean=(env -i HOME="$work")
for v in ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
  if [ -n "${!v:-}" ]; then clean+=("$v=${!v}"); fi
done
quantum="$prefix/bin/quantum"
mkdir "$work/elsewhere"
cd "$work/elsewhere"

"${clean[@]}" "$quantum" sports >"$work/sports.txt" || { cat "$work/sports.txt"; fail "quantum sports failed"; }
grep -q "^handball  ($prefix/share/quantum/rules/handball)" "$work/sports.txt" || { cat "$work/sports.txt"; fail "handball is not listed"; }
grep -q "players: blue: Blue's mallet; red: Red's mallet" "$work/sports.txt" || { cat "$work/sports.txt"; fail "air hockey's players are not listed"; }
grep -q "params:.* players=3" "$work/sports.txt" || { cat "$work/sports.txt"; fail "handball's parameters are not listed"; }

"${clean[@]}" "$quantum" play handball --seconds 20 --seed 2 --audio none --events "$work/handball.jsonl" >"$work/play.txt" \
  || { cat "$work/play.txt"; fail "quantum play handball failed"; }
grep -q '"type":"time_up"' "$work/handball.jsonl" || fail "the match by name did not play to its end"
grep -q "^final score: blue [0-9]* red [0-9]*" "$work/play.txt" || { cat "$work/play.txt"; fail "no final score"; }

if "${clean[@]}" "$quantum" play handbal --audio none 2>"$work/typo.txt"; then fail "a misspelt sport played"; fi
grep -q "did you mean 'handball'" "$work/typo.txt" || { cat "$work/typo.txt"; fail "no suggestion for a misspelt sport"; }

# A designer's own sport in a folder of their own, with a constant of its own in the sport table.
designs="$work/designs"
mkdir -p "$designs/duel/spec"
cp "$prefix/share/quantum/rules/airhockey/field.lua" "$designs/duel/field.lua"
cat >"$designs/duel/sport.lua" <<'LUA'
local sport = {
  name = "Duel",
  particles = 300,
  match = { seconds = 30, start = "blue" },
  points_per_goal = 2,
  phrases = { goal = "{team} scores" },
  on = {
    goal = function(game, e)
      local scorer = e.team == "blue" and "red" or "blue"
      game.award(scorer, sport.points_per_goal)
      game.say("goal", { team = scorer })
      game.respawn(e.team, 1)
    end,
  },
}
return sport
LUA
cat >"$designs/duel/spec/duel_spec.lua" <<'LUA'
describe("Duel", function()
  it("drops the puck in front of Blue's goal", function()
    local s = quantum.scenario("duel", { seed = 1 })
    local events = s:run(0.1)
    assert.are.equal("drop", events[1].type)
    assert.are.equal("in front of Blue's goal", events[1].actor)
  end)
end)
LUA
"${clean[@]}" QUANTUM_PATH="$designs" "$quantum" sports >"$work/sports.txt" || { cat "$work/sports.txt"; fail "quantum sports with QUANTUM_PATH failed"; }
grep -q "^duel  ($designs/duel)" "$work/sports.txt" || { cat "$work/sports.txt"; fail "QUANTUM_PATH's sport is not listed"; }
"${clean[@]}" QUANTUM_PATH="$designs" "$quantum" play duel --seconds 10 --audio none --quiet --events "$work/duel.jsonl" \
  || fail "quantum play duel (from QUANTUM_PATH) failed"
grep -q '"type":"time_up"' "$work/duel.jsonl" || fail "the designer's sport did not play to its end"
"${clean[@]}" QUANTUM_PATH="$designs" "$quantum" test duel >"$work/spec.txt" || { cat "$work/spec.txt"; fail "its spec failed"; }
grep -q "ok 1 specs" "$work/spec.txt" || { cat "$work/spec.txt"; fail "its spec did not run"; }

# The program alone, away from its data, says what it misses.
mkdir "$work/lone"
cp "$quantum" "$work/lone/quantum"
if "${clean[@]}" "$work/lone/quantum" play handball --audio none 2>"$work/lone.txt"; then fail "a program without its data played"; fi
grep -q "QUANTUM_DATA" "$work/lone.txt" || { cat "$work/lone.txt"; fail "no word on the missing data"; }
echo "install test: installed in $prefix, every check passed"
