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
#       <!-- example: bot model -->    Bots/DocBot.lua, with a mind folder
#           whose botdesc names the model's sensors and actuators, checked
#           by `evo check` (which builds the scene);
#     a `lua` block without one of these is a failure.
# A block that must not run says why on the line before its fence:
#   <!-- not run: REASON -->
# A block of output (no info string) marked
#   <!-- printed by the block above -->
# holds lines the file's last `sh` example (or environment example, run as
# above) printed: each of its lines must be one line of that output, exactly.
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
			if (info == "sh" || info == "lua" || info == "printed") {
				n = ++count[0]; out = dir "/" f ":" start
				gsub(/\//, "_", out); out = dir "/" n "-" substr(out, length(dir) + 2)
				print f, start, info, mark, out
			} else out = ""
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
			[ -z "$l" ] || grep -qxF -- "$l" "$tmp/last.out" || echo "$l"
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
		sed "s#\(^\|[ ;(|&]\)build/evo\b#\1$evo#g" "$block" >"$tmp/run.sh"
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
	elif [ "$mark" = example:_bot_model ]; then
		doc_mind "$block"
		timeout -k 5 120 "$evo" check "$tmp/Doc/Tasks/T.simbatch" >"$tmp/out" 2>&1
		result $? "$where" "the bot model example failed"
	else
		result 1 "$where" "a lua example needs <!-- example: environment --> or <!-- example: bot model --> before it"
	fi
done <"$tmp/examples"

[ -s "$tmp/examples" ] || { failed=$((failed + 1)); echo "FAIL: no example found"; }
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
