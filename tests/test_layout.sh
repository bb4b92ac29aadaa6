#!/bin/sh
# The layout rules of sim/README.md and STYLE.md, checked on the tree:
#   - every sim/ folder is in sim/README.md's table and has a README;
#   - a sim/ folder includes only its own headers and those of the folders
#     its row lets it use (core's public evo/*.h where the row says core);
#   - no file outside a folder includes that folder's *_internal.h, except
#     the folder's own tests (tests/sim/<folder>/);
#   - core/ includes nothing of sim/, and nothing includes a header by a
#     relative path ("../");
#   - bench/ includes no test code (tests/);
#   - sim/tasksim/tasksim.c reaches its scene only through
#     tasksim/simscene.h: it makes and frees a 2D or 3D scene and calls
#     nothing else of them, nor reads their bots (docs/architecture.md);
#   - world2d/'s and world3d/'s scenes call their physics engine only
#     through sim/scene/backend.h (the shims and fillings excepted);
#   - the reward and control kinds are named in sim/scene/kinds.c alone,
#     where each says the worlds it exists in;
#   - the rewards, controls, metrics and hooks of both scenes are
#     sim/scene/scoring's (docs/architecture.md, step 3): their types are
#     defined in scoring.h alone, the functions chosen by kind in
#     scoring.c alone, and both scenes pay them through evo_score_step;
#     the scenes' lookups by name are sim/scene/store.c's;
#   - every file docs/architecture.md names exists (a bare name such as
#     `step.c` must name exactly one file of the tree).
# Run from the repository root (make test does). Ends with
# "N passed, N failed" and exits non-zero on a failure.
cd "$(dirname "$0")/.." || exit 2
passed=0
failed=0
pass() { passed=$((passed + 1)); }
fail() {
	echo "FAIL: $*"
	failed=$((failed + 1))
}

# The table: "| `name/` | what | a, b, core |" -> "name: a b core".
table=$(awk -F'|' '/^\| `[a-z0-9]+\/` \|/ {
	name = $2; gsub(/[ `\/]/, "", name)
	uses = $4; gsub(/[,—]/, " ", uses); gsub(/  +/, " ", uses)
	print name ":" uses }' sim/README.md)
[ -n "$table" ] || fail "sim/README.md: no folder table found"

allowed() { # folder -> its allowed folders, space separated
	printf '%s\n' "$table" | awk -F: -v f="$1" '$1 == f { print $2 }'
}

# Every folder of sim/ is in the table and has a README.
for d in sim/*/; do
	f=$(basename "$d")
	if printf '%s\n' "$table" | grep -q "^$f:"; then pass; else
		fail "sim/$f/ is not in sim/README.md's table"; fi
	if [ -f "sim/$f/README.md" ]; then pass; else
		fail "sim/$f/ has no README.md"; fi
done

# Includes of each sim/ folder.
for d in sim/*/; do
	f=$(basename "$d")
	ok=$(allowed "$f")
	bad=0
	for src in "$d"*.c "$d"*.h "$d"*.cpp; do
		[ -f "$src" ] || continue
		for inc in $(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$src"); do
			case $inc in
			*/*) dir=${inc%%/*} ;;
			*) fail "$src: includes \"$inc\" without its folder"; bad=1; continue ;;
			esac
			[ "$dir" = "$f" ] && continue
			[ "$dir" = evo ] && dir=core
			case " $ok " in
			*" $dir "*) ;;
			*) fail "$src: includes \"$inc\", but sim/$f/ may use only:$ok"; bad=1 ;;
			esac
		done
	done
	[ $bad = 0 ] && pass
done

# Private headers stay in their folder (and its tests).
for h in sim/*/*_internal.h; do
	[ -f "$h" ] || continue
	f=$(basename "$(dirname "$h")")
	name="$f/$(basename "$h")"
	users=$(grep -rl --include='*.c' --include='*.h' --include='*.cpp' \
		"#include \"$name\"" sim tests bench firmware core 2>/dev/null |
		grep -v "^sim/$f/" | grep -v "^tests/sim/$f/")
	if [ -z "$users" ]; then pass; else
		fail "$name is private to sim/$f/, but included by: $(echo $users)"; fi
done

# core/ stands alone; no relative includes anywhere.
if grep -rn '#include "' core | grep -v '#include "evo/' |
	grep -qv '^core/src/'; then
	fail "core/include includes something other than evo/*.h"
else pass; fi
rel=$(grep -rn '#include "[^"]*\.\./' core sim tests bench firmware 2>/dev/null)
if [ -z "$rel" ]; then pass; else fail "relative includes: $rel"; fi

# bench/ includes no test code.
benchbad=""
for src in bench/*.c; do
	for inc in $(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$src"); do
		[ -f "tests/$inc" ] && benchbad="$benchbad $src:$inc"
	done
done
if [ -z "$benchbad" ]; then pass; else fail "bench includes test code:$benchbad"; fi

# One tick flows downward in world2d/: the element queries and the pieces
# that run each tick (sensors, actuators, rewards) call nothing of the
# scene's storage, grid or step, which drive them. Checked on the library
# the build made (EVO_BUILD, default build), by the symbols its objects use.
lib=${EVO_BUILD:-build}/libevohost.a
if [ -f "$lib" ]; then
	tmp=$(mktemp -d)
	syms() { # --defined-only -g | -u, then object names
		opt=$1
		shift
		for o in "$@"; do
			nm -A $opt "$lib" 2>/dev/null | awk -v o="$o" -F: \
				'$2 == o { n = split($3, f, " "); print f[n] }'
		done | sort -u
	}
	syms "--defined-only -g" scene.o step.o grid.o >"$tmp/above"
	if [ -s "$tmp/above" ]; then pass; else
		fail "$lib: no symbols of scene.o, step.o and grid.o"; fi
	for piece in query sensors actuators rewards; do
		syms -u "$piece.o" >"$tmp/used"
		up=$(comm -12 "$tmp/above" "$tmp/used")
		if [ -z "$up" ]; then pass; else
			fail "world2d/$piece.c calls up into scene.c, grid.c or step.c: $(echo $up)"; fi
	done
	rm -rf "$tmp"
else
	fail "no $lib: build first (make test-bins)"
fi

# tasksim.c never asks its scene's dimension: it makes and frees the scene
# and calls nothing else of world2d/ or world3d/ (simscene.c does).
calls=$(grep -o 'evo_\(scene\|scene3d\|bot\|bot3d\)_[a-z0-9_]*(\|->bot\[' \
	sim/tasksim/tasksim.c | grep -v '_create($\|_destroy($' | sort -u)
if [ -z "$calls" ]; then pass; else
	fail "sim/tasksim/tasksim.c reaches its scene around simscene.h: $(echo $calls)"; fi

# The scenes reach their physics only through the backend interface
# (sim/scene/backend.h): no file of world2d/ but its Box2D shim and filling
# calls world.h's functions, none of world3d/ but its ODE shim and filling
# calls world3d.h's.
direct=$(grep -l 'evo_\(world\|body\)_[a-z_]*(' sim/world2d/*.c |
	grep -v '^sim/world2d/backend_box2d.c$')
direct="$direct $(grep -l 'evo_\(world3d\|body3d\)_[a-z_]*(' sim/world3d/*.c |
	grep -v '^sim/world3d/world_ode.c$\|^sim/world3d/backend_ode.c$')"
if [ -z "$(echo $direct)" ]; then pass; else
	fail "scene files calling their engine around sim/scene/backend.h: $(echo $direct)"; fi

# The kinds' names are sim/scene/kinds.c's alone (2D and 3D read them).
names=$(grep -rl --include='*.c' '"ClosingOnTarget"\|"NextOnTimeout"' sim |
	grep -v '^sim/scene/kinds.c$')
if [ -z "$names" ]; then pass; else
	fail "reward or control names outside sim/scene/kinds.c: $(echo $names)"; fi

# One scoring for both scenes (step 3): the reward, control, metric and
# hook types are scoring.h's alone; no file but scoring.c chooses a reward
# or control function by its kind; both steps hand the tick's rewards and
# controls to evo_score_step; no scene's storage compares names itself.
defs=$(grep -rl --include='*.h' \
	'typedef struct evo_\(reward_def\|control_def\|metric\|scene_hooks\) {' sim |
	grep -v '^sim/scene/scoring.h$')
if [ -z "$defs" ]; then pass; else
	fail "reward, control, metric or hook types outside sim/scene/scoring.h: $(echo $defs)"; fi
cases=$(grep -rl --include='*.c' 'case EVO_\(RW\|CF\)_' sim |
	grep -v '^sim/scene/scoring.c$')
if [ -z "$cases" ]; then pass; else
	fail "reward or control functions chosen outside sim/scene/scoring.c: $(echo $cases)"; fi
for f in sim/world2d/rewards.c sim/world3d/rewards3d.c; do
	if grep -q 'evo_score_step(' "$f"; then pass; else
		fail "$f does not score its scene through evo_score_step"; fi
done
own=$(grep -l 'strcmp(' sim/world2d/scene.c sim/world3d/scene3d.c)
if [ -z "$own" ]; then pass; else
	fail "scene storage comparing names around sim/scene/store.c: $(echo $own)"; fi

# Every file docs/architecture.md names exists.
if [ -f docs/architecture.md ]; then
	missing=""
	for p in $(grep -o '`[a-z0-9_./-]*\.\(c\|h\|cpp\|lua\|md\)`' docs/architecture.md |
		tr -d '`' | sort -u); do
		case $p in
		*/*) [ -f "$p" ] || missing="$missing $p" ;;
		*) # a bare name must name exactly one file of the tree
			n=$(find core sim lua firmware -name "$p" | wc -l)
			[ "$n" -eq 1 ] || missing="$missing $p($n found)" ;;
		esac
	done
	if [ -z "$missing" ]; then pass; else
		fail "docs/architecture.md names files that do not exist:$missing"; fi
else
	fail "docs/architecture.md is missing"
fi

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
