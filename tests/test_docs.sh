#!/bin/sh
# Every example in README.md and docs/*.md runs as written, so the docs
# cannot drift from the code. An example is a fenced block whose info
# string is `sh` or `lua`:
#   - `sh`: run from the repository root with `sh -e`, each `build/evo` the
#     evo under test ($EVO_BUILD/evo), without a display, within a time
#     limit; it must exit 0. Its mktemp folders are made in the test's own
#     temporary folder (TMPDIR), removed at the end.
#   - `lua`: the line before the fence says what the block is,
#       <!-- example: environment -->  Envs/DocExample.lua in a copy of
#           minds/Avoid, run headless for two short episodes (so its init,
#           reset and hooks all run);
#       <!-- example: 3D environment -->  the same in a copy of
#           minds/Wheeled3D (DEMO3DSIM, its trained Avoid3D skill);
#       <!-- example: bot model -->    Bots/DocBot.lua, with a mind folder
#           whose botdesc names the model's sensors and actuators, checked
#           by `evo check` (which builds the scene);
#     a `lua` block without one of these is a failure;
#   - `c`: <!-- example: C, in a function of (PARAMS) with HEADER --> before
#     it: compiled (cc -fsyntax-only, warnings as errors) as the body of a
#     function of PARAMS, after #include "HEADER" (from core/include).
# A block that must not run says why on the line before its fence:
#   <!-- not run: REASON -->
# A block of output (no info string) marked
#   <!-- printed by the block above -->
# holds lines the file's last `sh` example (or environment example, run as
# above) printed: each of its lines must be one line of that output, exactly,
# but for a "..." in it, which stands for any text (a temporary folder, a
# time), so what varies is masked where the reader sees it.
# Every other fenced block (output, a table, a synopsis, a file) says on
# the line before its fence what checks it; a block that says nothing is a
# failure, so no example goes unchecked:
#   <!-- checked by FILE -->  FILE (a test of tests/) compares the block
#       with what evo does; FILE must exist and name the doc file (its path
#       from the root, e.g. docs/remote.md), and read the block by its
#       mark: FILE holds "checked by FILE", or calls doc_block("DOC" of
#       tests/support/doc_block.h once for each block of DOC so marked; so
#       the mark cannot lie silently;
#   <!-- format: KIND -->     an example file, parsed by
#       tests/docs/test_doc_formats.c;
#   <!-- printed by: build/bench/NAME [ARGS] -->  a benchmark's figures
#       (benchmarks do not run here): bench/NAME.c must exist, and each line
#       of the block must be in the form one of its printf formats prints
#       (tests/docs/printed_form.pl), so a row cannot drift from the bench;
#   <!-- synopsis of: evo CMD ... -->  every option the block shows is
#       one `evo CMD --help` shows;
#   <!-- not an example: WHAT -->  notation, not a line a user types or
#       sees (a grammar, a folder layout).
# DOC_FILES="FILE ..." checks those files only (default README.md docs/*.md).
# Ends with "N passed, N failed" and exits non-zero on a failure.
cd "$(dirname "$0")/.." || exit 2
evo=${EVO_BUILD:-build}/evo
passed=0
failed=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# an example's own temporary folders (mktemp) go into ours, removed with it
export TMPDIR="$tmp"
unset DISPLAY WAYLAND_DISPLAY

# One line per example: FILE LINE INFO MARK, MARK being the HTML comment
# on the line before the fence ("-" when there is none); the block's text
# in $tmp/blocks/N.
mkdir -p "$tmp/blocks"
for f in ${DOC_FILES:-README.md docs/*.md}; do
	awk -v f="$f" -v dir="$tmp/blocks" '
		/^```/ && !inb {
			inb = 1; info = substr($0, 4); start = FNR
			mark = prev ~ /^<!-- .* -->$/ ? prev : "-"
			gsub(/^<!-- | -->$/, "", mark); gsub(/ /, "_", mark)
			if (info == "" && mark == "printed_by_the_block_above") info = "printed"
			if (info == "") info = "other"
			n = ++count[0]; out = dir "/" f ":" start
			gsub(/\//, "_", out); out = dir "/" n "-" substr(out, length(dir) + 2)
			print f, start, info, mark, out
			printf "" > out
			next
		}
		/^```/ && inb { inb = 0; next }
		inb && out != "" { print > out }
		{ if ($0 != "") prev = $0 }
	' "$f"
done >"$tmp/examples"

result() { # ok? where what
	if [ "$1" = 0 ]; then
		passed=$((passed + 1))
		echo "ok   $2"
	else
		failed=$((failed + 1))
		echo "FAIL $2: $3"
		[ -f "$tmp/out" ] && sed 's/^/    /' "$tmp/out" | tail -n 15
	fi
}

# A copy of minds/Avoid with task T.simbatch running environment ENV.
avoid_copy() {
	rm -rf "$tmp/Avoid" && cp -r minds/Avoid "$tmp/"
	printf 'TYPE:DEMOSIM\nBOTMODEL:BotType8\nMASTERSKILL:Avoid\nENV:%s\n' \
		"$1" >"$tmp/Avoid/Tasks/T.simbatch"
}

# A copy of minds/Wheeled3D with task T.simbatch running 3D environment ENV.
wheeled3d_copy() {
	rm -rf "$tmp/Wheeled3D" && cp -r minds/Wheeled3D "$tmp/"
	mkdir -p "$tmp/Wheeled3D/Envs"
	printf 'TYPE:DEMO3DSIM\nBOTMODEL:Wheeled3D\nMASTERSKILL:Avoid3D\nENV:%s\n' \
		"$1" >"$tmp/Wheeled3D/Tasks/T.simbatch"
}

# A mind folder Doc whose botdesc lists the sensors and actuators the bot
# model in $1 adds (by their name = "..." options), with one neural skill
# reading every sensor and driving every actuator, to be trained (so it
# needs no network), and a plain environment.
doc_mind() {
	rm -rf "$tmp/Doc" && mkdir -p "$tmp/Doc/Skills/Drive" "$tmp/Doc/Tasks" \
		"$tmp/Doc/Bots" "$tmp/Doc/Envs"
	cp "$1" "$tmp/Doc/Bots/DocBot.lua"
	sens=$(grep -E 'bot:(proximity|distance|zone|bearing|presence|object_detector|movement|random|constant|holding)' "$1" |
		sed -n 's/.*name *= *"\([^"]*\)".*/\1/p')
	acts=$(grep -E 'bot:(wheel|claw)' "$1" | sed -n 's/.*name *= *"\([^"]*\)".*/\1/p')
	{
		echo SENSORS
		for s in $sens; do echo "$s:doc"; done
		echo ACTUATORS
		for a in $acts; do echo "$a:doc"; done
	} >"$tmp/Doc/Doc.botdesc"
	{
		echo Drive
		echo "input:$(echo $sens | wc -w)"
		for s in $sens; do printf 'SE:%s ' "$s"; done
		echo
		echo "output:$(echo $acts | wc -w)"
		for a in $acts; do printf 'MO:%s ' "$a"; done
		echo
		echo neural
	} >"$tmp/Doc/Skills/Drive/Drive.ades"
	cat >"$tmp/Doc/Envs/Plain.lua" <<'EOF'
local env = {}
function env.init(scene, task)
	env.bot = scene:bot{ x = 0, y = 0 }
	scene:control("NextOnTimeout", { bot = env.bot, ticks = 100 })
end
return env
EOF
	printf 'TYPE:LEARNSIM\nBOTMODEL:DocBot\nMASTERSKILL:Drive\nLEARNINGSKILL:Drive\nLEARNINGMETHOD:NEAT\nNUMGEN:1\nENV:Plain\n' \
		>"$tmp/Doc/Tasks/T.simbatch"
}

# A C example, compiled (not run) as the body of a function of the
# parameters its mark names, with the header it names, as a user's code
# would be: the calls must exist and take what the block gives them.
c_example() { # file line where block
	raw=$(head -n $(($2 - 1)) "$1" | grep -v '^$' | tail -n 1)
	params=$(echo "$raw" | sed -n 's/.*in a function of (\(.*\)) with .*/\1/p')
	header=$(echo "$raw" | sed -n 's/.*) with \([^ ]*\) -->$/\1/p')
	{
		echo "#include \"$header\""
		echo "void doc_example($params);"
		echo "void doc_example($params)"
		echo "{"
		cat "$4"
		echo "}"
	} >"$tmp/example.c"
	${CC:-cc} -std=c11 -Wall -Wextra -Werror -Wpedantic -fsyntax-only \
		-Icore/include "$tmp/example.c" >"$tmp/out" 2>&1
	result $? "$3" "the C example does not compile"
}

# A block that is not run: its mark must say what checks it.
other_block() { # file where mark block
	case $3 in
	checked_by_?*)
		what=${3#checked_by_}
		if [ ! -f "$what" ]; then
			result 1 "$2" "checked by $what, which is no file"
		elif ! grep -qF -- "$1" "$what"; then
			result 1 "$2" "checked by $what, which does not name $1"
		elif grep -qF -- "checked by $what" "$what"; then
			# it reads the block itself, by its mark
			result 0 "$2 checked by $what"
		elif [ "$(grep -cF -- "doc_block(\"$1\"" "$what")" -ge \
			"$(grep -cxF -- "<!-- checked by $what -->" "$1")" ]; then
			# it reads each such block with doc_block()
			result 0 "$2 checked by $what"
		else
			result 1 "$2" "checked by $what, which does not read the block by its mark"
		fi
		;;
	format:_?*)
		result 0 "$2 checked by tests/docs/test_doc_formats.c"
		;;
	printed_by:_build/bench/?*)
		cmd=$(echo "${3#printed_by:_}" | tr _ ' ')
		name=${3#printed_by:_build/bench/}
		name=${name%%_-*} # its arguments start with a -
		src=bench/$name.c
		if [ ! -f "$src" ]; then
			result 1 "$2" "printed by $cmd, but there is no $src"
			return
		fi
		missing=$(perl tests/docs/printed_form.pl "$src" "$4")
		if [ -n "$missing" ]; then
			{ echo "no format of $src prints:"; echo "$missing"; } >"$tmp/out"
			result 1 "$2" "lines not in the form $cmd prints"
		else
			result 0 "$2 in the form $cmd prints"
		fi
		;;
	synopsis_of:_evo_?*)
		# every option it shows is one the commands' --help shows
		cmds=$(echo "${3#synopsis_of:_}" | tr _ ' ' | sed 's/\bevo\b//g; s/  */ /g')
		for c in $cmds; do "$evo" "$c" --help; done >"$tmp/help" 2>&1
		missing=$(grep -oE -- '(^|[[ ])--?[a-z][-a-z]*' "$4" | sed 's/^[[ ]//' | sort -u |
			while IFS= read -r o; do
				grep -qE -- "(^|[^-a-z])$o([^-a-z]|\$)" "$tmp/help" || echo "$o"
			done)
		if [ -n "$missing" ]; then
			{ echo "options --help does not show:"; echo "$missing"; } >"$tmp/out"
			result 1 "$2" "a synopsis with options evo$cmds --help does not show"
		else
			result 0 "$2 options as evo$cmds --help shows them"
		fi
		;;
	not_an_example:_?*)
		echo "skip $2: not an example: $(echo "${3#not_an_example:_}" | tr _ ' ')"
		;;
	*)
		result 1 "$2" "a block no test checks: run it (sh), or mark it (see the header of tests/test_docs.sh)"
		;;
	esac
}

while read -r file line info mark block; do
	where="$file:$line ($info)"
	if [ "$info" = printed ]; then
		# the output of this file's last sh example, kept in $tmp/last.out
		rm -f "$tmp/out"
		if [ "$last_file" != "$file" ] || [ ! -f "$tmp/last.out" ]; then
			result 1 "$where" "no sh example of this file ran before it"
			continue
		fi
		missing=$(while IFS= read -r l; do
			case $l in
			'') ;;
			*...*) # "..." stands for what varies (a folder, a time)
				re=$(printf '%s\n' "$l" | sed 's/[][\\.*^$+?(){}|]/\\&/g; s/\\\.\\\.\\\./.*/g')
				grep -qxE -- "$re" "$tmp/last.out" || echo "$l" ;;
			*) grep -qxF -- "$l" "$tmp/last.out" || echo "$l" ;;
			esac
		done <"$block")
		if [ -n "$missing" ]; then
			{ echo "not printed:"; echo "$missing"; echo "printed:"; cat "$tmp/last.out"; } >"$tmp/out"
			result 1 "$where" "lines the example above did not print"
		else
			result 0 "$where"
		fi
		continue
	fi
	rm -f "$tmp/out"
	if [ "$info" = c ] && [ "${mark#example:_C,_in_a_function_of_}" != "$mark" ]; then
		c_example "$file" "$line" "$where" "$block"
		continue
	fi
	if [ "$info" != sh ] && [ "$info" != lua ]; then
		other_block "$file" "$where" "$mark" "$block"
		continue
	fi
	case $mark in
	not_run:_?*)
		echo "skip $where: $(echo "${mark#not_run:_}" | tr _ ' ')"
		continue
		;;
	not_run*)
		result 1 "$where" "'not run' without a reason"
		continue
		;;
	esac
	if [ "$info" = sh ]; then
		sed "s#\(^\|[ ;(|&=]\)build/evo\b#\1$evo#g" "$block" >"$tmp/run.sh"
		# stdin is not the list of examples (mpirun reads its stdin)
		timeout -k 5 120 sh -e "$tmp/run.sh" >"$tmp/out" 2>&1 </dev/null
		rc=$?
		cp "$tmp/out" "$tmp/last.out"
		last_file=$file
		result $rc "$where" "the example failed"
	elif [ "$mark" = example:_environment ]; then
		avoid_copy DocExample
		cp "$block" "$tmp/Avoid/Envs/DocExample.lua"
		timeout -k 5 120 "$evo" run "$tmp/Avoid/Tasks/T.simbatch" --headless \
			--episodes 2 --ticks 300 >"$tmp/out" 2>&1
		rc=$?
		cp "$tmp/out" "$tmp/last.out"
		last_file=$file
		result $rc "$where" "the environment example failed"
	elif [ "$mark" = example:_3D_environment ]; then
		wheeled3d_copy DocExample
		cp "$block" "$tmp/Wheeled3D/Envs/DocExample.lua"
		timeout -k 5 120 "$evo" run "$tmp/Wheeled3D/Tasks/T.simbatch" \
			--headless --episodes 2 --ticks 300 >"$tmp/out" 2>&1
		rc=$?
		cp "$tmp/out" "$tmp/last.out"
		last_file=$file
		result $rc "$where" "the 3D environment example failed"
	elif [ "$mark" = example:_bot_model ]; then
		doc_mind "$block"
		timeout -k 5 120 "$evo" check "$tmp/Doc/Tasks/T.simbatch" >"$tmp/out" 2>&1
		result $? "$where" "the bot model example failed"
	else
		result 1 "$where" "a lua example needs <!-- example: environment -->, <!-- example: 3D environment --> or <!-- example: bot model --> before it"
	fi
done <"$tmp/examples"

[ -s "$tmp/examples" ] || { failed=$((failed + 1)); echo "FAIL: no example found"; }
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
