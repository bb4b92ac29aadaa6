#!/bin/sh
# docs/firmware.md's figures are what the firmware build prints:
#   - the indented block after `<!-- printed by make firmware-size ... -->`
#     holds lines `make firmware-size` prints, each exactly;
#   - the image and state sizes of the Collect mind quoted elsewhere on the
#     page (the firmware's start line, "the mind state (N bytes for
#     Collect") are the ones that output gives;
#   - the indented block after `<!-- printed by build/bench/bench_firmware
#     ... -->` holds what that benchmark prints (make bench runs it), but
#     for the figures of time, which vary from run to run.
# Run after the firmware is built (make test runs it after firmware-test).
# Ends with "N passed, N failed"; exits non-zero on a failure.
cd "$(dirname "$0")/../.." || exit 2
passed=0
failed=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
check() { # ok? what
	if [ "$1" = 0 ]; then passed=$((passed + 1)); echo "ok   $2"
	else failed=$((failed + 1)); echo "FAIL $2"; fi
}

make -s --no-print-directory firmware-size >"$tmp/sizes" 2>&1
check $? "make firmware-size runs"
awk '/^<!-- printed by make firmware-size/ { f = 1; next }
	f && /^    / { print substr($0, 5); next }
	f { exit }' docs/firmware.md >"$tmp/quoted"
[ -s "$tmp/quoted" ]
check $? "docs/firmware.md quotes make firmware-size"
while IFS= read -r line; do
	grep -qxF "$line" "$tmp/sizes"
	rc=$?
	[ $rc = 0 ] || { echo "    docs/firmware.md: $line"; echo "    make firmware-size prints:"; sed 's/^/      /' "$tmp/sizes"; }
	check $rc "docs/firmware.md's line is what make firmware-size prints: $line"
done <"$tmp/quoted"

image=$(sed -n 's/^m3 *Collect: image \([0-9]*\) bytes.*mind state \([0-9]*\) bytes.*/\1/p' "$tmp/sizes")
state=$(sed -n 's/^m3 *Collect: image \([0-9]*\) bytes.*mind state \([0-9]*\) bytes.*/\2/p' "$tmp/sizes")
grep -q "# mind Collect: image $image bytes in flash at 0000e000, state $state bytes in RAM" docs/firmware.md
check $? "the firmware's start line in docs/firmware.md gives image $image and state $state bytes"
grep -q "mind state ($state bytes for Collect" docs/firmware.md
check $? "docs/firmware.md gives Collect's mind state as $state bytes"

# bench_firmware's figures: every line but the host's time, and the
# transfer's last line up to its wall time (both vary from run to run).
make -s --no-print-directory build/bench/bench_firmware >"$tmp/make" 2>&1 &&
	build/bench/bench_firmware >"$tmp/bench" 2>&1
rc=$?
[ $rc = 0 ] || sed 's/^/    /' "$tmp/make" "$tmp/bench" | tail -n 20
check $rc "build/bench/bench_firmware runs"
awk '/^<!-- printed by build\/bench\/bench_firmware/ { f = 1; next }
	f && /^    / { print substr($0, 5); next }
	f { exit }' docs/firmware.md >"$tmp/quoted"
[ "$(wc -l <"$tmp/quoted")" -ge 5 ]
check $? "docs/firmware.md quotes bench_firmware"
while IFS= read -r line; do
	case $line in
	*"host:"*"ns per tick"*) continue ;;
	*"wall time"*)
		want=${line%%;*}
		grep -qF -- "$want;" "$tmp/bench" ;;
	*) want=$line; grep -qxF -- "$line" "$tmp/bench" ;;
	esac
	rc=$?
	[ $rc = 0 ] || { echo "    bench_firmware prints:"; sed 's/^/      /' "$tmp/bench"; }
	check $rc "docs/firmware.md's line is what bench_firmware prints: $want"
done <"$tmp/quoted"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
