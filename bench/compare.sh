#!/bin/sh
# make bench-compare BASE=<commit>: bench_world and bench_evaluate of an
# earlier commit beside this tree's, in the same run.
#
# The earlier commit is exported into build/bench-base/<commit> and built
# there; then the two builds' benchmarks run in turns, ROUNDS times (the
# order swapped every round, so a slow spell of a shared machine does not
# fall on one side only), and the best figure of each build is printed
# with the ratio of this tree's to the base's. A ratio at or above 1 is no
# worse. Timings on a shared machine are noisy; the ratio of one run holds.
# Where valgrind is installed, the instructions a DEMOSIM run and a short
# learning run execute are counted in each build too: a figure no other
# process on the machine can move.
#
# usage: sh bench/compare.sh BASE [ROUNDS]   (from the repository root)
set -eu
base=${1:?usage: bench/compare.sh BASE [ROUNDS]}
rounds=${2:-3}
rev=$(git rev-parse --short "$base^{commit}") || {
	echo "bench-compare: '$base' is not a commit of this repository" >&2
	exit 2
}
dir=build/bench-base/$rev
if [ ! -x "$dir/build/bench/bench_evaluate" ] || [ ! -x "$dir/build/evo" ]; then
	echo "bench-compare: building $rev in $dir"
	rm -rf "$dir" && mkdir -p "$dir"
	git archive "$rev" | tar -x -C "$dir"
	make -C "$dir" -j2 build/evo build/bench/bench_world build/bench/bench_evaluate >"$dir.log" 2>&1 || {
		echo "bench-compare: the build of $rev failed; see $dir.log" >&2
		exit 1
	}
fi
make -j2 build/evo build/bench/bench_world build/bench/bench_evaluate >/dev/null

out=build/bench-base/compare-$rev
rm -rf "$out" && mkdir -p "$out"
# A benchmark exits non-zero when its own bar is not met; that is its
# figure, not a failure here. A run that prints no figure fails below.
run() { # tree bench round
	(cd "$1" && "build/bench/$2") >"$out/$2-$3-$(basename "$1")" 2>&1 || true
}
i=1
while [ "$i" -le "$rounds" ]; do
	echo "bench-compare: round $i of $rounds"
	for b in bench_world bench_evaluate; do
		if [ $((i % 2)) -eq 1 ]; then
			run "$dir" $b $i; run . $b $i
		else
			run . $b $i; run "$dir" $b $i
		fi
	done
	i=$((i + 1))
done

# The best of the rounds: the highest ticks/s, ratio and evaluations/s.
best() { # bench tree awk-program
	cat "$out"/"$1"-*-"$(basename "$2")" | awk "$3" | sort -g | tail -n 1
}
report() { # what bench awk-program
	a=$(best "$2" "$dir" "$3")
	b=$(best "$2" . "$3")
	if [ -z "$a" ] || [ -z "$b" ]; then
		echo "bench-compare: no figure for '$1' in $out" >&2
		exit 1
	fi
	echo "$1 $a $b" | awk '{ printf "  %-34s %12.2f %12.2f   %5.2f\n", $1, $2, $3, $3 / $2 }'
}
echo "best of $rounds rounds                  base $rev   this tree   ratio"
report full-tick-ticks/s bench_world '/evo full tick/ { print $(NF - 3) }'
report tick/floor bench_world '/ratio .* of the floor/ { print $2 }'
report physics-floor-ticks/s bench_world '/physics floor/ { print $(NF - 3) }'
report evaluations/s-1-thread bench_evaluate '/1 thread :/ { print $4 }'
report evaluations/s-2-threads bench_evaluate '/2 threads:/ { print $3 }'

# Instructions, which no other process on the machine changes: callgrind
# counts what a DEMOSIM run and a short learning run (one thread) execute
# in each build. Fewer is better, so here a ratio at or below 1 is no worse.
if command -v valgrind >/dev/null 2>&1; then
	task=tests/data/golden/tasks/Avoid-NEAT-golden.simbatch
	count() { # tree label command...
		tree=$1 label=$2
		shift 2
		(cd "$tree" && valgrind --tool=callgrind \
			--callgrind-out-file=/dev/null "$@" 2>&1) |
			sed -n 's/.*Collected : \([0-9]*\).*/\1/p' >"$out/ir-$label-$(basename "$tree")"
	}
	for tree in "$dir" .; do
		count "$tree" demo build/evo run minds/Avoid/Tasks/Avoid-DEMO.simbatch \
			--headless --seed 3 --episodes 2 --ticks 3000
		t=$(mktemp -d)
		cp -r minds/Avoid "$t/" && cp "$task" "$t/Avoid/Tasks/"
		count "$tree" learn build/evo run "$t/Avoid/Tasks/$(basename "$task")" \
			--seed 1 --threads 1 --run "$t/run"
		rm -rf "$t"
	done
	echo "instructions (callgrind)                base $rev   this tree   ratio"
	for label in demo learn; do
		a=$(cat "$out/ir-$label-$(basename "$dir")")
		b=$(cat "$out/ir-$label-.")
		if [ -z "$a" ] || [ -z "$b" ]; then
			echo "bench-compare: callgrind counted nothing for '$label'" >&2
			exit 1
		fi
		echo "$label $a $b" | awk '{ printf "  %-34s %12.0f %12.0f   %5.3f\n", $1, $2, $3, $3 / $2 }'
	done
else
	echo "bench-compare: no valgrind, so no instruction counts (apt-get install valgrind)"
fi
echo "bench-compare: the benchmarks' own output is in $out"
