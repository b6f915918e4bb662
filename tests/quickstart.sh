#!/usr/bin/env bash
# quickstart.sh: the README's first commands run as written (issue 30,
# point 4).
# The Quick start is two commands, from the top of a clone: the set-up
# and the shipped tablecloth (run here off a terminal, where it prints a
# summary; .ci/setup itself installs packages and is CI's), then make
# check. The README says how drape gets on the PATH, and that way works:
# the export it shows, and make install.
set -u

DRAPE=${DRAPE:-src/drape}
case $DRAPE in /*) ;; *) DRAPE=$PWD/$DRAPE ;; esac
top=$(cd "$(dirname "$0")/.." && pwd)	# the source tree
build=$(cd "$(dirname "$DRAPE")/.." && pwd)	# the build tree
readme=$top/README.md
tmp=$(mktemp -d) || exit 99
trap 'rm -rf "$tmp"' EXIT
failed=0
fail() { echo "FAIL: $*"; failed=1; }

# the indented lines of the section titled $1 (one command a line, a
# continued line joined)
commands() {
	awk -v title="## $1" '
		$0 == title { inside = 1; next }
		/^## / { inside = 0 }
		inside && /^    [^ ]/ {
			line = substr($0, 5)
			while (line ~ /\\$/ && (getline more) > 0) {
				sub(/\\$/, "", line); sub(/^ +/, "", more); line = line more
			}
			print line
		}' "$readme"
}

echo "== the Quick start: two commands"
commands "Quick start" >"$tmp/quick"
[ "$(wc -l <"$tmp/quick")" -eq 2 ] || fail "the Quick start has $(wc -l <"$tmp/quick") commands: $(cat "$tmp/quick")"
[ "$(sed -n 1p "$tmp/quick")" = '.ci/setup && src/drape scenes/tablecloth.scene' ] ||
	fail "the Quick start's first command is '$(sed -n 1p "$tmp/quick")'"
[ "$(sed -n 2p "$tmp/quick")" = 'make check' ] || fail "the Quick start's second command is '$(sed -n 2p "$tmp/quick")'"
[ -x "$top/.ci/setup" ] || fail ".ci/setup is not executable"
# its run, off a terminal: the progress and a summary, exit 0
(cd "$top" && "$DRAPE" scenes/tablecloth.scene) </dev/null >"$tmp/out" 2>"$tmp/err"
rc=$?
[ $rc -eq 0 ] && grep -q '^steps ' "$tmp/out" ||
	fail "src/drape scenes/tablecloth.scene off a terminal: exit $rc: $(head -n 3 "$tmp/err")"

echo "== drape on the PATH"
tr '\n' ' ' <"$readme" | grep -q '`sudo make install`' || fail "the README does not say make install"
path_line=$(awk '/^## drape on your PATH/ { on = 1 } on && /^    export PATH=/ { print substr($0, 5); exit }' "$readme")
[ "$path_line" = 'export PATH="$PWD/src:$PATH"' ] || fail "no PATH line in the README: '$path_line'"
# as written, from the top of the (build) tree
found=$(cd "$build" && env -i HOME="$HOME" PATH=/usr/bin:/bin sh -c "$path_line; command -v drape")
[ "$found" = "$build/src/drape" ] || fail "after '$path_line', drape is '$found'"
# make install puts the binary and the three pages in place
if ${MAKE:-make} -C "$build" install DESTDIR="$tmp/inst" >"$tmp/install" 2>&1; then
	prefix=$(sed -n 's/^prefix = //p' "$build/Makefile")
	"$tmp/inst$prefix/bin/drape" --version >/dev/null || fail "the installed drape does not run"
	for p in man1/drape.1 man5/drape-scene.5 man5/drape-replay.5; do
		[ -f "$tmp/inst$prefix/share/man/$p" ] || fail "make install: no $p"
	done
else
	fail "make install: $(tail -n 3 "$tmp/install")"
fi

[ $failed -eq 0 ] && echo "all passed"
exit $failed
