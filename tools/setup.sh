#!/usr/bin/env bash
# Installs the Debian packages the project uses (idempotent, non-interactive) and builds Release,
# every optional part included (CONTRIBUTING.md, "Build options", says which package is whose):
# every target, or only those named (`tools/setup.sh quantum quantum_tests`). With --play first,
# only what a match needs: the engine's build and run packages, not the test tools, and a new
# build folder configured without the tests and the benchmarks (tools/play.sh). Safe to run again: it installs
# only what is missing and rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

play=0
if [ "${1:-}" = "--play" ]; then play=1; shift; fi

engine_packages=(
  build-essential cmake pkg-config
  libbox2d-dev                 # reference physics backend
  libopencv-dev libopencv-contrib-dev  # tracking (ArUco markers), debug snapshots
  libeigen3-dev                # tracking: Kalman filters
  libfreenect-dev              # tracking: a live Kinect, and its recording format
  liblo-dev                    # tracking: TUIO over OSC
  libluajit-5.1-dev            # field files and rules
  libopenal-dev libespeak-ng-dev libsndfile1-dev  # sound: mixer, announcer voice, clips
  libpocketsphinx-dev libsphinxbase-dev pocketsphinx-en-us libsamplerate0-dev  # quantum listen: a speech recognizer
  libcairo2-dev                # tracking: quantum-synth --markers, the markers as a PDF at their printed size
  libcli11-dev nlohmann-json3-dev
  zlib1g-dev                   # logs named .gz, written and read compressed
  libx11-dev                   # the desk: its window's screen size, and a clear error without a display
  libboost-math-dev            # chi-square distribution for the rule specs' statistics
)
test_packages=(
  lua-busted                   # rule specs (quantum test)
  gnuplot-nox                  # quantum balance --plot
  ffmpeg                       # the desk's videos (--video); ffprobe checks them in the tests
  xvfb xauth imagemagick xdotool  # the tests open the desk's window on a virtual display, press its keys and photograph it
  file                         # cpack's Debian package (tests/install)
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-dev        # tools/sanitize.sh: the sanitizers and libFuzzer (docs/reliability.md)
)
packages=("${engine_packages[@]}")
if ((!play)); then packages+=("${test_packages[@]}"); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

mkdir -p build
log=build/setup.log
configure=(-DCMAKE_BUILD_TYPE=Release)
# A play leaves a build folder's choice as it was; a new one gets no tests or benchmarks, whose
# packages it lacks.
if ((!play)); then configure+=(-DQUANTUM_BUILD_TESTS=ON -DQUANTUM_BUILD_BENCHMARKS=ON)
elif [ ! -f build/CMakeCache.txt ]; then configure+=(-DQUANTUM_BUILD_TESTS=OFF -DQUANTUM_BUILD_BENCHMARKS=OFF); fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
if ! { cmake -S . -B build "${configure[@]}" && cmake --build build -j"$(nproc)" "${targets[@]}"; } >"$log" 2>&1; then
  cat "$log"
  echo "setup: the build failed (log above, also in $log)" >&2
  exit 1
fi
echo "setup: built (log in $log)"
