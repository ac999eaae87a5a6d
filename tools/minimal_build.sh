#!/usr/bin/env bash
# The engine with every optional part left out (CONTRIBUTING.md, "Build options"): configures a
# build folder (default build-minimal) with every QUANTUM_WITH_* OFF and neither tests nor
# benchmarks, builds `quantum`, plays a short match and a simulation with it, and checks that it
# links none of the left-out packages and that each left-out module's command or option says
# which CMake option brings it back, exiting 1 as a bad command line does.
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${1:-build-minimal}"

cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DQUANTUM_WITH_TRACKING=OFF -DQUANTUM_WITH_DESK=OFF \
  -DQUANTUM_WITH_RECOGNIZER=OFF -DQUANTUM_WITH_REFERENCE=OFF -DQUANTUM_BUILD_TESTS=OFF -DQUANTUM_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$dir" -j"$(nproc)" --target quantum >/dev/null
quantum="$dir/quantum"

fail() { echo "minimal build: $*" >&2; exit 1; }

modules=$("$quantum" --version | tail -n 1)
[ "$modules" = "modules: tracking off, desk off, recognizer off, reference off" ] || fail "--version says '$modules'"
# What the program itself links (the libraries it names: others, such as OpenAL's, bring their own).
linked=$(readelf -d "$quantum" | grep -Eo 'lib(pocketsphinx|sphinxbase|samplerate|cairo|opencv_[a-z0-9_]+|freenect[a-z_]*|lo|box2d|X11)\.so' || true)
[ -z "$linked" ] || fail "quantum links what its options left out: $(echo $linked)"

ALSOFT_DRIVERS=null "$quantum" play airhockey --seconds 10 --audio none --quiet >/dev/null || fail "quantum play failed"
"$quantum" simulate airhockey --seconds 2 --particles 500 >/dev/null || fail "quantum simulate failed"

# `left_out OPTION COMMAND...`: the command exits 1, naming -DOPTION=ON.
left_out() {
  local option=$1 said status=0
  shift
  said=$("$quantum" "$@" 2>&1 >/dev/null) || status=$?
  [ "$status" = 1 ] || fail "quantum $*: exit $status, not 1"
  [[ "$said" == *"this quantum was built without "*"(-D$option=ON)"* ]] || fail "quantum $*: said '$said'"
}
left_out QUANTUM_WITH_RECOGNIZER listen match.wav match.jsonl
left_out QUANTUM_WITH_TRACKING track kinect
left_out QUANTUM_WITH_TRACKING play airhockey --input tuio:3333 --audio none
left_out QUANTUM_WITH_DESK play airhockey --view --audio none
left_out QUANTUM_WITH_DESK play airhockey --input mouse --audio none
left_out QUANTUM_WITH_DESK simulate airhockey --snapshot shot.png
left_out QUANTUM_WITH_REFERENCE simulate airhockey --backend box2d
echo "minimal build: $quantum plays, and says what it was built without"
