#!/bin/sh
# docs/firmware.md's walk through `make firmware-run` ("Trying it under
# QEMU"), run as written from the repository root after make firmware-test
# has built the firmware and fw_run: the firmware under QEMU on an slcan
# pseudo-terminal takes a mind from `evo flash`, and drives the body `evo
# serve --robot` runs on the other port; and the two evo flash lines the
# docs quote are the walk's (but for its folder and the transfer's time).
# Ends with "N passed, N failed".
cd "$(dirname "$0")/../.." || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export TMPDIR="$tmp"
# the block after the "not run" line that names this script
awk '/^<!-- not run: / && index($0, "tests/firmware/test_firmware_run.sh") { want = 1; next }
	want && /^```sh$/ { inb = 1; next }
	inb && /^```$/ { exit }
	inb { print }' docs/firmware.md >"$tmp/walk.sh"
passed=0
failed=0
check() { # what pattern
	if grep -q "$2" "$tmp/out"; then
		passed=$((passed + 1))
		echo "ok   $1"
	else
		failed=$((failed + 1))
		echo "FAIL $1: no line matching '$2'"
	fi
}
if [ ! -s "$tmp/walk.sh" ]; then
	echo "FAIL docs/firmware.md: no block after the line naming this script"
	failed=1
else
	timeout -k 5 120 sh -e "$tmp/walk.sh" >"$tmp/out" 2>&1 </dev/null
	rc=$?
	if [ $rc = 0 ]; then passed=$((passed + 1)); echo "ok   the walk runs"
	else failed=$((failed + 1)); echo "FAIL the walk exits $rc"; fi
	check "evo flash switches the firmware's mind" \
		'^evo flash: the robot runs mind Collect from the tick after'
	check "the firmware says the switch" \
		'^# mind Collect: image [0-9]* bytes in flash at 0000c000'
	check "fw_run starts the body's episode" \
		'^fw_run: slcan-pty:?link=.*/bus2: a body; episode 1 started with seed 1'
	check "the firmware's commands drive the body" \
		'bus2: [0-9]* ticks: [1-9][0-9]* commanded in time'
	# the evo flash lines docs/firmware.md quotes from this walk: the
	# same but for the temporary folder and the transfer's time
	mask='s#/tmp/[^ ]*/bus#DIR/bus#; s#again, [0-9.]* s;#again, T s;#'
	grep '^    evo flash: .*Collect.*\(segments, to\|from the tick after\)' \
		docs/firmware.md | sed "s/^    //; $mask" >"$tmp/quoted"
	sed "$mask" "$tmp/out" >"$tmp/masked"
	missing=$(while IFS= read -r l; do
		grep -qxF -- "$l" "$tmp/masked" || echo "$l"
	done <"$tmp/quoted")
	if [ "$(wc -l <"$tmp/quoted")" = 2 ] && [ -z "$missing" ]; then
		passed=$((passed + 1))
		echo "ok   docs/firmware.md's evo flash lines are what the walk printed"
	else
		failed=$((failed + 1))
		echo "FAIL docs/firmware.md's evo flash lines are what the walk printed:"
		cat "$tmp/quoted"
	fi
	[ $failed = 0 ] || sed 's/^/    /' "$tmp/out" | tail -n 30
fi
echo "$passed passed, $failed failed"
[ $failed = 0 ]
