#!/usr/bin/env bash
# The reliability run (docs/reliability.md): builds build-sanitize with clang, the address and
# undefined behaviour sanitizers on every target and the libFuzzer targets, then runs the CTest
# suite there, every label and the fuzzers included (each for QUANTUM_FUZZ_SECONDS, 60 by default).
# Arguments go to ctest: `tools/sanitize.sh -LE long` leaves out the long tests while working.
# Installs nothing itself: tools/setup.sh (run first by tools/test.sh) installs clang.
set -euo pipefail
cd "$(dirname "$0")/.."

dir=build-sanitize
mkdir -p "$dir"
log=$dir/build.log
if ! { cmake -S . -B "$dir" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
         -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
         -DQUANTUM_SANITIZE=ON -DQUANTUM_FUZZ=ON -DQUANTUM_FUZZ_SECONDS="${QUANTUM_FUZZ_SECONDS:-60}" &&
       cmake --build "$dir" -j"$(nproc)"; } >"$log" 2>&1; then
  cat "$log"
  echo "sanitize: the build failed (log above, also in $log)" >&2
  exit 1
fi
echo "sanitize: built (log in $log)"

# Any report fails the test that made it. LuaJIT's known false positives are listed, with why,
# in tools/sanitizers/.
supp=$PWD/tools/sanitizers
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"
export ALSOFT_DRIVERS="${ALSOFT_DRIVERS:-null}"
ctest --test-dir "$dir" --output-on-failure --timeout 600 -j"$(nproc)" "$@"
