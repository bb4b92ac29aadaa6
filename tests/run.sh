#!/bin/sh
# Runs test binaries, TEST_JOBS of them at a time (default 2, the cores
# `make test` is sized for), shows each one's output in one piece as it
# ends, and closes with the sum of their "N passed, N failed" lines. A
# binary that crashes, exits non-zero or prints no such line counts as one
# failure. Exits non-zero on any failure.
#
# Tests may run beside each other: each makes its files in a folder of its
# own (mktemp) and takes LCM ports and remote names from its process id,
# as it must anyway on a machine where other builds run their tests.
#
# The slowest binaries (below, by path under tests/ or their build's
# tests/) start first, so the two slots end close together; any other
# binary runs in the order given. A new slow test only needs naming here
# to be started early; unnamed, it still runs.
SLOW_FIRST="sim/learn/test_learn sim/learn/test_learn_teams
sim/remote/test_corridor sim/remote/test_learn_remote sim/cmd/test_run
test_docs.sh sim/cmd/test_golden sim/cluster/test_cluster
sim/remote/test_robot sim/remote/test_can_robot sim/remote/test_remote
sim/lua/test_lua_sandbox sim/cmd/test_check"

# One binary: $1 the results folder, $2 the binary. Its output, its time
# and its counts go to the terminal together (under a lock, so two ending
# at once do not interleave); "PASSED FAILED" to a file for the sum.
if [ "$1" = --one ]; then
	dir=$2
	t=$3
	id=$(printf '%s' "$t" | tr '/' '_')
	log=$dir/$id.log
	start=$(date +%s.%N)
	# a binary that hangs (a deadlock, a sanitizer stuck at exit) fails
	# after TEST_TIMEOUT seconds (600: six times the slowest), instead of
	# stalling the whole run
	timeout -k 30 "${TEST_TIMEOUT:-600}" "$t" >"$log" 2>&1
	rc=$?
	[ $rc -ne 124 ] && [ $rc -ne 137 ] ||
		echo "(stopped after ${TEST_TIMEOUT:-600} s: it hung)" >>"$log"
	# each binary's time, so the slow ones are plain in a CI log
	took=$(awk -v s="$start" -v e="$(date +%s.%N)" \
		'BEGIN { printf "%.1f", e - s }')
	line=$(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$log" | tail -n 1)
	p=0
	f=0
	if [ -n "$line" ]; then
		p=${line%% passed*}
		f=${line#*, }
		f=${f%% failed*}
	fi
	{
		echo "== $t"
		cat "$log"
		echo "-- $t: $took s"
		if [ $rc -ne 0 ] || [ -z "$line" ]; then
			echo "FAILED: $t (exit status $rc)"
			[ -z "$line" ] || [ "$f" -gt 0 ] || f=$((f + 1))
			[ -n "$line" ] || f=$((f + 1))
		fi
	} >"$log.shown"
	flock "$dir/lock" cat "$log.shown"
	echo "$p $f" >"$dir/$id.sum"
	exit 0
fi

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
: >"$dir/lock"

# the binaries given, the slow ones first (each once, in SLOW_FIRST's
# order), then the rest in their order
for s in $SLOW_FIRST; do
	for t in "$@"; do
		case "$t" in */"$s" | "$s") echo "$t" ;; esac
	done
done >"$dir/order"
for t in "$@"; do
	grep -qxF "$t" "$dir/order" || echo "$t"
done >>"$dir/order"

xargs -r -n 1 -P "${TEST_JOBS:-2}" sh "$0" --one "$dir" <"$dir/order"

passed=0
failed=0
for t in "$@"; do
	id=$(printf '%s' "$t" | tr '/' '_')
	if [ -r "$dir/$id.sum" ]; then
		read -r p f <"$dir/$id.sum"
	else
		echo "FAILED: $t (not run)"
		p=0
		f=1
	fi
	passed=$((passed + p))
	failed=$((failed + f))
done
echo "Total: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
