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
#   - sim/tasksim/tasksim.c reaches its scene only through the scene
#     model's core (sim/scene/core.h, and its dimension's table): it makes
#     and frees a 2D or 3D scene and calls nothing else of them, nor reads
#     their bots (docs/architecture.md);
#   - world2d/'s and world3d/'s scenes call their physics engine only
#     through sim/scene/backend.h (the shims and fillings excepted);
#   - the reward and control kinds are named in sim/scene/kinds.c alone,
#     where each says the worlds it exists in;
#   - one Lua binding for both scenes (docs/architecture.md, step 5): no
#     sim/lua/ file calls a scene's own functions (world3d's, or world2d's
#     adds, lookups and placing) but that dimension's table, lua_dim3d.c
#     or lua_dim2d.c, and the piece, sensor and actuator kinds the binding
#     offers are sim/scene/kinds.c's rows (no method table of sim/lua/
#     names one);
#   - one sensor struct for both worlds (step 4): sim/scene/sensor.h's;
#   - the rewards, controls, metrics and hooks of both scenes are
#     sim/scene/scoring's (docs/architecture.md, step 3): their types are
#     defined in scoring.h alone, the functions chosen by kind in
#     scoring.c alone, and both scenes pay them through sim/scene/core.c
#     (evo_core_score, evo_core_pay);
#     the scenes' lookups by name are sim/scene/store.c's;
#   - the elements of both scenes are one struct, sim/scene/element.h's;
#   - every file docs/architecture.md names exists (a bare name such as
#     `step.c` must name exactly one file of the tree);
#   - no host source (sim/*/*.c, *.cpp) is over 800 lines, but for the few
#     of an allow-list still being split;
#   - no include circle: no source includes a .c file, no header reaches
#     itself through its includes, and no two sources each reach the
#     other's header (the allow-list's pairs excepted).
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
# and calls nothing else of world2d/ or world3d/ (the scene's core and its
# evo_scene_dim do, sim/scene/core.h); the bots it reads are the core's
# one evo_bot (sim/scene/bot.h, view.c).
calls=$(grep -o 'evo_\(scene\|scene3d\|bot3d\)_[a-z0-9_]*(\|scene3\?d\?->bot\[' \
	sim/tasksim/tasksim.c | grep -v '_create($\|_destroy($' | sort -u)
if [ -z "$calls" ]; then pass; else
	fail "sim/tasksim/tasksim.c reaches its scene around sim/scene/core.h: $(echo $calls)"; fi

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

# One Lua binding (step 5): each scene's own functions are called from its
# dimension's table alone (lua_evo.c makes env.obstacles' 2D entries); the kinds'
# methods come from kinds.c's rows, never from a method table of their own.
calls3d=$(grep -l 'evo_\(scene3d\|bot3d\|sensor3d\)_[a-z_]*(' sim/lua/*.c |
	grep -v '^sim/lua/lua_dim3d.c$')
calls2d=$(grep -l 'evo_\(scene_add\|scene_find\|scene_place\|bot\|sensor\|body\)_[a-z_]*(' \
	sim/lua/*.c | grep -v '^sim/lua/lua_dim2d.c$\|^sim/lua/lua_evo.c$')
if [ -z "$calls3d$calls2d" ]; then pass; else
	fail "sim/lua/ files calling a scene around its dimension's table: $(echo $calls3d $calls2d)"; fi
rows=$(grep -l '{"\(proximity\|cylinder\|claw\|propeller\|sphere\)", *[a-z_]*}' sim/lua/*.c)
if [ -z "$rows" ]; then pass; else
	fail "kinds given methods of their own around sim/scene/kinds.c's rows: $(echo $rows)"; fi
[ ! -f sim/lua/lua_scene3d.c ] && pass || fail "sim/lua/lua_scene3d.c is back: one binding serves both scenes"

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
if grep -q 'evo_score_step(' sim/scene/core.c; then pass; else
	fail "sim/scene/core.c does not score the scenes through evo_score_step"; fi
if grep -q 'evo_core_pay(' sim/scene/scoring.c; then pass; else
	fail "sim/scene/scoring.c does not pay the rewards through sim/scene/core.c's evo_core_pay"; fi
own=$(grep -l 'strcmp(' sim/world2d/scene.c sim/world3d/scene3d.c)
if [ -z "$own" ]; then pass; else
	fail "scene storage comparing names around sim/scene/store.c: $(echo $own)"; fi

# One struct per piece for both worlds (step 4): evo_X_def and evo_X of
# the sensor, actuator, element and bot are sim/scene/X.h's alone, their
# kinds kinds.h's; no world defines one of its own, and no 3D struct or
# kind of before (evo_X3d, EVO3D_SENSOR_...) is back anywhere.
for part in sensor:SENSOR actuator:ACTUATOR element:ELEM bot:BOT; do
	name=${part%:*} caps=${part#*:}
	defs=$(grep -rl --include='*.h' --include='*.c' \
		-e "struct evo_$name\(_def\)\? {" -e "struct evo_${name}3d" \
		-e "enum evo_$name\(3d\)\?_kind" sim | grep -v "^sim/scene/$name.h\$")
	if [ -z "$defs" ]; then pass; else
		fail "$name structs or kinds outside sim/scene/$name.h and kinds.h: $(echo $defs)"; fi
	old=$(grep -rlw --exclude=test_layout.sh \
		-e "evo_${name}3d" -e "evo_${name}3d_def" -e "evo_${name}_kind" sim tests bench docs
		grep -rl --exclude=test_layout.sh "EVO3D_${caps}_" sim tests bench docs)
	if [ -z "$old" ]; then pass; else
		fail "3D's own $name struct or kind is back: $(echo $old)"; fi
done

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

# No host source over 800 lines: a file that long owns more than one thing
# (STYLE.md); split it by what its parts own. The allow-list holds files
# others are changing now; take a file off it when it is split (a listed
# file of 800 lines or fewer fails, so the list cannot go stale).
MAX_LINES=800
LONG_ALLOWED="
"
for src in sim/*/*.c sim/*/*.cpp; do
	[ -f "$src" ] || continue
	n=$(wc -l <"$src")
	listed=0
	case "$LONG_ALLOWED" in *"
$src
"*) listed=1 ;; esac
	if [ "$n" -le $MAX_LINES ] && [ $listed = 1 ]; then
		fail "$src: $n lines, yet on tests/test_layout.sh's allow-list of long files: take it off"
	elif [ "$n" -gt $MAX_LINES ] && [ $listed = 0 ]; then
		fail "$src: $n lines, over $MAX_LINES: split it by what its parts own (STYLE.md)"
	else pass; fi
done

# No include circle. The edges: each sim/ file to the sim/ headers it
# includes ("folder/name.h").
incs=$(for f in sim/*/*.c sim/*/*.cpp sim/*/*.h; do
	[ -f "$f" ] || continue
	sed -n 's/^#include "\([^"]*\)".*/\1/p' "$f" | while read -r inc; do
		case $inc in
		*.c | *.cpp) echo "$f sim/$inc" ;;
		*) [ -f "sim/$inc" ] && echo "$f sim/$inc" ;;
		esac
	done
done)
[ -n "$incs" ] || fail "no includes found under sim/"
# No source includes a .c file.
cinc=$(printf '%s\n' "$incs" | awk '$2 ~ /\.(c|cpp)$/ { print $1 ": " $2 }')
if [ -z "$cinc" ]; then pass; else fail "sources include .c files: $cinc"; fi
# No header reaches itself: tsort finds a loop among the headers' edges.
if printf '%s\n' "$incs" | awk '$1 ~ /\.h$/ && $1 != $2' |
	tsort >/dev/null 2>&1; then pass; else
	fail "a header include circle: $(printf '%s\n' "$incs" |
		awk '$1 ~ /\.h$/ && $1 != $2' | tsort 2>&1 >/dev/null | tr '\n' ' ')"
fi
# No two sources each reach the other's header (A.c reaches B.h through its
# includes, and B.c reaches A.h): they would be one module in two files, or
# share a type that belongs in a header of its own (as learn/eval_seeds.h
# holds what evaluate.c and evaluate_remote.c share). The allow-list holds
# the pairs of folders others are changing now, or that this check found
# and no one has split yet; a listed pair no longer mutual fails.
MUTUAL_ALLOWED="
"
mutual=$(printf '%s\n' "$incs" | awk '
	{ to[$1] = to[$1] " " $2; files[$1] = 1 }
	function reach(f,    todo, n, i, k, parts, x) {
		delete seen; n = 0
		todo[++n] = f
		while (n > 0) {
			x = todo[n--]
			k = split(to[x], parts, " ")
			for (i = 1; i <= k; i++)
				if (!(parts[i] in seen)) {
					seen[parts[i]] = 1
					todo[++n] = parts[i]
				}
		}
	}
	END {
		for (f in files) if (f ~ /\.(c|cpp)$/) {
			h = f; sub(/\.(c|cpp)$/, ".h", h)
			reach(f)
			for (x in seen) if (x != h && x ~ /\.h$/) r[f, x] = 1
			header[f] = h
		}
		for (a in header) for (b in header)
			if (a < b && ((a, header[b]) in r) && ((b, header[a]) in r))
				print a " " b
	}' | sort)
for pair in $(printf '%s\n' "$mutual" | tr ' ' '+'); do
	pair=$(echo "$pair" | tr '+' ' ')
	case "$MUTUAL_ALLOWED" in
	*"
$pair
"*) pass ;;
	*) fail "$(echo "$pair" | sed 's/ / and /') each include the other's header (directly or through headers): move what they share into a header of its own" ;;
	esac
done
for pair in $(printf '%s\n' "$MUTUAL_ALLOWED" | tr ' ' '+'); do
	pair=$(echo "$pair" | tr '+' ' ')
	case "
$mutual
" in
	*"
$pair
"*) pass ;;
	*) fail "$pair: no longer include each other; take them off tests/test_layout.sh's allow-list" ;;
	esac
done

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
