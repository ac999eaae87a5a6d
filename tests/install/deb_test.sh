#!/usr/bin/env bash
# The Debian package (docs/install.md): built by CPack from this build, it holds the programs in
# /usr/bin and the engine's data in /usr/share/quantum, names its runtime dependencies as
# Debian's packages, and its programs, unpacked anywhere, find their data.
# Run by CTest (install_deb); arguments: the build folder, cpack.
set -euo pipefail
build="$(realpath "$1")"
cpack="${2:-cpack}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "deb test: $*" >&2; exit 1; }

(cd "$build" && "$cpack" -G DEB -B "$work/package" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack failed"; }
debs=("$work"/package/quantum_*.deb)
[ -f "${debs[0]}" ] || { cat "$work/cpack.log"; fail "no quantum_*.deb"; }
deb="${debs[0]}"
echo "deb test: built $(basename "$deb")"

dpkg-deb -c "$deb" | awk '{print $NF}' >"$work/files.txt"
for f in ./usr/bin/quantum ./usr/bin/quantum-synth ./usr/share/quantum/rules/lib/two_teams.lua \
         ./usr/share/quantum/rules/powerups/penalty.lua ./usr/share/quantum/rules/airhockey/sport.lua \
         ./usr/share/quantum/sounds/goal.wav ./usr/share/quantum/markers/markers.pdf ./usr/share/doc/quantum/README.md; do
  grep -qxF "$f" "$work/files.txt" || fail "$f is not in the package"
done
if grep -v -e '^\./usr/bin/' -e '^\./usr/share/quantum/' -e '^\./usr/share/doc/quantum/' -e '^\./usr/$' -e '^\./usr/bin/$' \
     -e '^\./usr/share/$' -e '^\./usr/share/doc/$' -e '^\./$' "$work/files.txt"; then
  fail "the files above are outside /usr/bin, /usr/share/quantum and /usr/share/doc/quantum"
fi

[ "$(dpkg-deb -f "$deb" Package)" = quantum ] || fail "the package is not named quantum"
depends="$(dpkg-deb -f "$deb" Depends)"
echo "deb test: Depends: $depends"
# The libraries it links, as dpkg-shlibdeps names their packages, and what it runs by name.
for p in libluajit-5.1-2 libopenal1 libespeak-ng1 libsndfile1 libbox2d2 libfreenect0.5 liblo7 libopencv-core406 \
         libpocketsphinx3 libcairo2 lua-busted pocketsphinx-en-us; do
  grep -qE "(^|, )$p( |,|$)" <<<"$depends" || fail "Depends does not name $p"
done

# Unpacked into a folder of its own (not installed), the program still finds its data: relative
# to itself, not to where it was built.
dpkg-deb -x "$deb" "$work/root"
clean=(env -i HOME="$work")
for v in ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
  if [ -n "${!v:-}" ]; then clean+=("$v=${!v}"); fi
done
cd "$work"
"${clean[@]}" "$work/root/usr/bin/quantum" play airhockey --seconds 5 --audio none --quiet --events "$work/events.jsonl" \
  || fail "the unpacked quantum did not play"
grep -q '"type":"time_up"' "$work/events.jsonl" || fail "the unpacked quantum's match did not end"
echo "deb test: every check passed"
