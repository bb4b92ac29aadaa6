#!/bin/sh
# Runs test binaries, shows their output, and closes with the sum of their
# "N passed, N failed" lines. A binary that crashes, exits non-zero or
# prints no such line counts as one failure. Exits non-zero on any failure.
passed=0
failed=0
log=$(mktemp)
for t in "$@"; do
	echo "== $t"
	start=$(date +%s.%N)
	"$t" >"$log" 2>&1
	rc=$?
	cat "$log"
	# each binary's time, so the slow ones are plain in a CI log
	awk -v s="$start" -v e="$(date +%s.%N)" -v t="$t" \
		'BEGIN { printf "-- %s: %.1f s\n", t, e - s }'
	line=$(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$log" | tail -n 1)
	if [ -n "$line" ]; then
		p=${line%% passed*}
		f=${line#*, }
		f=${f%% failed*}
		passed=$((passed + p))
		failed=$((failed + f))
	fi
	if [ $rc -ne 0 ] || [ -z "$line" ]; then
		echo "FAILED: $t (exit status $rc)"
		[ -z "$line" ] || [ "$f" -gt 0 ] || failed=$((failed + 1))
		[ -n "$line" ] || failed=$((failed + 1))
	fi
done
rm -f "$log"
echo "Total: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
