#!/bin/sh
# README.md's figures and pictures are what evo makes:
#   - the block after `<!-- checked by tests/docs/test_readme_run.sh -->`
#     in README.md holds lines `make run`
#     prints (generation lines up to their species count, the replay's
#     lines whole): the same training (minds/Seek, --seed 1, any number of
#     threads) must print each of them;
#   - docs/learning.md's blocks after the same mark quote the same replay
#     lines, and one generation line;
#   - docs/img/curve.png is that run's learning curve, byte for byte;
#   - docs/img/viewer.png is what README's --screenshot command saves;
#   - docs/img/openmaze-gallery.png is the gallery of docs/openended.md's
#     OPENENDED run.
# A figure or picture that no longer matches fails with the command that
# makes it again. Ends with "N passed, N failed"; exits non-zero on a failure.
cd "$(dirname "$0")/../.." || exit 2
evo=${EVO_BUILD:-build}/evo
passed=0
failed=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
unset DISPLAY WAYLAND_DISPLAY

check() { # ok? what
	if [ "$1" = 0 ]; then passed=$((passed + 1)); echo "ok   $2"
	else failed=$((failed + 1)); echo "FAIL $2"; fi
}

# The lines of FILE's fenced blocks marked as checked here.
marked() {
	awk '/^<!-- checked by tests\/docs\/test_readme_run.sh -->$/ { f = 1; next }
	f && /^```/ { if (++fence == 2) { f = 0; fence = 0 }; next }
	f && fence == 1 { print }' "$1"
}

# The quoted lines, from the README.
marked README.md >"$tmp/quoted"
[ -s "$tmp/quoted" ]
check $? "README.md has a figures block for make run"

# make run's training, as the Makefile runs it.
cp -r minds/Seek "$tmp/"
"$evo" run "$tmp/Seek/Tasks/Seek-NEAT.simbatch" --seed 1 --run "$tmp/run" >"$tmp/out" 2>&1
check $? "the Seek example trains ($evo run Seek-NEAT.simbatch --seed 1)"

while IFS= read -r line; do
	case $line in
	gen\ *)
		# up to the species count: the speed and times vary
		want=$(echo "$line" | awk '{ print $1, $2, $3, $4, $5, $6, $7, $8 }')
		awk '{ print $1, $2, $3, $4, $5, $6, $7, $8 }' "$tmp/out" | grep -qxF "$want" ;;
	*) grep -qxF "$line" "$tmp/out" ;;
	esac
	rc=$?
	[ $rc = 0 ] || { echo "    README.md quotes: $line"; echo "    make run prints:"; grep -E '^(gen |replay|  )' "$tmp/out" | sed 's/^/      /' | tail -n 5; }
	check $rc "README.md's figure is what make run prints: $line"
done <"$tmp/quoted"

# docs/learning.md quotes the same replay
marked docs/learning.md >"$tmp/learning"
grep '^replay\|^  ' "$tmp/quoted" | while IFS= read -r line; do
	grep -qxF "$line" "$tmp/learning" || { echo "    docs/learning.md lacks: $line"; exit 1; }
done
check $? "docs/learning.md quotes make run's replay as README.md does"

# and one of its generation lines, up to the species count
want=$(grep '^gen [0-9]*/25 ' "$tmp/learning" | awk '{ print $1, $2, $3, $4, $5, $6, $7, $8 }')
[ -n "$want" ] && awk '{ print $1, $2, $3, $4, $5, $6, $7, $8 }' "$tmp/out" | grep -qxF "$want"
rc=$?
[ $rc = 0 ] || echo "    docs/learning.md quotes: $want"
check $rc "docs/learning.md's generation line is one make run prints"

cmp -s "$tmp/run/curve.png" docs/img/curve.png
rc=$?
[ $rc = 0 ] || echo "    make it again: make run && cp build/run/seek-neat/curve.png docs/img/curve.png"
check $rc "docs/img/curve.png is make run's learning curve"

"$evo" run minds/Collect/Tasks/Collect-DEMO.simbatch --seed 1 --ticks 200 \
	--screenshot "$tmp/viewer.png" >/dev/null 2>&1 && cmp -s "$tmp/viewer.png" docs/img/viewer.png
rc=$?
[ $rc = 0 ] || echo "    make it again: build/evo run minds/Collect/Tasks/Collect-DEMO.simbatch --seed 1 --ticks 200 --screenshot docs/img/viewer.png"
check $rc "docs/img/viewer.png is what README's --screenshot command saves"
grep -q 'Collect-DEMO.simbatch --seed 1 --ticks 200 --screenshot' README.md
check $? "README.md gives the command that makes docs/img/viewer.png"

GALLERY="minds/OpenMaze/Tasks/OpenMaze.simbatch --seed 1 --generations 30 --no-save --run /tmp/oe-gallery"
"$evo" run ${GALLERY%/tmp/oe-gallery} "$tmp/oe-gallery" >/dev/null 2>&1 &&
	cmp -s "$tmp/oe-gallery/gallery.png" docs/img/openmaze-gallery.png
rc=$?
[ $rc = 0 ] || echo "    make it again: rm -rf /tmp/oe-gallery && build/evo run $GALLERY && cp /tmp/oe-gallery/gallery.png docs/img/openmaze-gallery.png"
check $rc "docs/img/openmaze-gallery.png is the gallery of docs/openended.md's run"
grep -qF "$GALLERY" docs/openended.md
check $? "docs/openended.md gives the command that makes docs/img/openmaze-gallery.png"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
