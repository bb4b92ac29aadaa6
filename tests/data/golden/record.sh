#!/bin/sh
# Records the golden outputs that tests/sim/cmd/test_golden.c compares against:
# the DEMOSIM traces and rewards of the four 2D examples, and the logs,
# champions and reports of short learning runs. tests/data/golden/README.md
# says what each file is.
#
#   sh tests/data/golden/record.sh EVO [OUTDIR]
#
# Run it from a repository root: it runs the mind folders of ./minds with
# the evo binary EVO (which finds its lua/ beside itself, as build/evo
# does). It writes into OUTDIR, by default this script's folder. Learning
# runs train copies of the mind folders in a temporary folder, never
# minds/ itself. The commands here and in tests/sim/cmd/test_golden.c must stay
# the same.
set -eu

if [ $# -lt 1 ] || [ $# -gt 2 ]; then
	echo "usage: sh tests/data/golden/record.sh EVO [OUTDIR]" >&2
	exit 2
fi
evo=$1
here=$(cd "$(dirname "$0")" && pwd)
out=${2:-$here}
if [ ! -d minds/Avoid ] || [ ! -d minds/DoublePoleNV ]; then
	echo "record.sh: run it from the repository root (no minds/ here)" >&2
	exit 2
fi
if [ ! -x "$evo" ]; then
	echo "record.sh: $evo is not an executable" >&2
	exit 2
fi
mkdir -p "$out"
tmp=$(mktemp -d /tmp/evo-golden-record-XXXXXX)

fail() {
	echo "record.sh: $1 failed; its output is in $tmp" >&2
	exit 1
}

# demo NAME TASK: a headless DEMOSIM run, seed 3, 2 episodes of 1000 ticks;
# NAME.out is its standard output, NAME.trace.gz its trace.
demo() {
	"$evo" run "$2" --headless --seed 3 --episodes 2 --ticks 1000 \
		--trace "$tmp/$1.trace" >"$tmp/$1.out" 2>"$tmp/$1.err" ||
		fail "$1"
	cp "$tmp/$1.out" "$out/$1.out"
	gzip -9n <"$tmp/$1.trace" >"$out/$1.trace.gz"
	echo "$1: $(wc -l <"$tmp/$1.trace") trace lines"
}

# learn NAME MIND TASK: a LEARNSIM run of the copy $tmp/NAME/MIND (made and
# prepared by the caller), seed 1, 2 threads, run folder $tmp/NAME/run.
# NAME.log.csv is its log.csv without the two time columns (as
# cli_fitness_log in tests/support/cli.c: each line up to its 7th comma),
# NAME.champion.net its champion, NAME.report.txt the lines of its output
# that carry figures and no time or path.
learn() {
	"$evo" run "$tmp/$1/$2/Tasks/$3" --seed 1 --threads 2 \
		--run "$tmp/$1/run" >"$tmp/$1/out.txt" 2>&1 || fail "$1"
	sed -E 's/^(([^,]*,){7}).*/\1/' "$tmp/$1/run/log.csv" >"$out/$1.log.csv"
	cp "$tmp/$1/run/champion.net" "$out/$1.champion.net"
	grep -E '^(solved in generation |replay on unseen |  champion: |  untrained )' \
		"$tmp/$1/out.txt" >"$out/$1.report.txt" || true
	echo "$1: $(($(wc -l <"$out/$1.log.csv") - 1)) generations"
}

# copy NAME MIND: minds/MIND copied to $tmp/NAME/MIND.
copy() {
	mkdir -p "$tmp/$1"
	cp -r "minds/$2" "$tmp/$1/"
}

demo avoid-demo minds/Avoid/Tasks/Avoid-DEMO.simbatch
demo gto-demo minds/GTO/Tasks/GTO-DEMO.simbatch
demo gtoa-demo minds/GTO/Tasks/GTOA-DEMO.simbatch
demo collect-demo minds/Collect/Tasks/Collect-DEMO.simbatch

# The literature tasks as shipped; DPNV cut to 3 generations.
copy xor-neat XOR
learn xor-neat XOR XOR-NEAT.simbatch
copy dpv-neat DoublePole
learn dpv-neat DoublePole DPV-NEAT.simbatch
copy dpnv-neat DoublePoleNV
sed -i 's/^NUMGEN:.*/NUMGEN:3/' "$tmp/dpnv-neat/DoublePoleNV/Tasks/DPNV-NEAT.simbatch"
learn dpnv-neat DoublePoleNV DPNV-NEAT.simbatch

# Avoid in the 2D world, with this folder's small tasks; GENETIC and
# ANNEALING train a layered network (layers:1), as tests/sim/learn/test_learn.c
# does.
for method in NEAT GENETIC ANNEALING; do
	name=avoid-$(echo "$method" | tr 'A-Z' 'a-z')
	copy "$name" Avoid
	cp "$here/tasks/Avoid-$method-golden.simbatch" "$tmp/$name/Avoid/Tasks/"
	if [ "$method" != NEAT ]; then
		sed -i 's/^layers:0$/layers:1/' "$tmp/$name/Avoid/Skills/Avoid/Avoid.ades"
	fi
	learn "$name" Avoid "Avoid-$method-golden.simbatch"
done

rm -rf "$tmp"
echo "recorded into $out"
