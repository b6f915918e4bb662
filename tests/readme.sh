#!/usr/bin/env bash
# readme.sh: the synopsis in README.md ("What is there", between the
# "synopsis:" markers, indented 4 spaces) is the usage that `drape --help`
# prints, line for line, up to its first blank line.
#   tests/readme.sh            check (make check runs it)
#   tests/readme.sh --write    rewrite the block from the binary (make readme)
set -u

DRAPE=${DRAPE:-src/drape}
srcdir=${srcdir:-.}
readme=$srcdir/README.md
begin='<!-- synopsis: begin (make readme writes this from `drape --help`) -->'
end='<!-- synopsis: end -->'

tmp=$(mktemp -d /tmp/drape-readme-XXXXXX) || exit 1
trap 'rm -rf "$tmp"' EXIT
"$DRAPE" --help >"$tmp/help" || { echo "FAIL: $DRAPE --help exited $?"; exit 1; }
sed '/^$/,$d' "$tmp/help" | sed 's/^/    /' >"$tmp/want"
[ -s "$tmp/want" ] || { echo "FAIL: $DRAPE --help printed no usage"; exit 1; }
grep -qxF "$begin" "$readme" && grep -qxF "$end" "$readme" ||
	{ echo "FAIL: README.md has no synopsis markers ($begin ... $end)"; exit 1; }

if [ "${1:-}" = --write ]; then
	awk -v b="$begin" -v e="$end" -v f="$tmp/want" '
		$0 == b { print; print ""; while ((getline l < f) > 0) print l; print ""; skip = 1; next }
		$0 == e { skip = 0 }
		!skip' "$readme" >"$tmp/README.md" && cat "$tmp/README.md" >"$readme" || exit 1
	echo "README.md: synopsis written from $DRAPE --help"
	exit 0
fi

awk -v b="$begin" -v e="$end" '$0 == e { on = 0 } on && NF { print } $0 == b { on = 1 }' \
	"$readme" >"$tmp/got"
if ! diff -u "$tmp/got" "$tmp/want"; then
	echo "FAIL: README.md's synopsis (-) is not drape --help's usage (+):"
	echo "run 'make readme' (tests/readme.sh --write) and commit README.md"
	exit 1
fi
echo "ok: README.md's synopsis is drape --help's usage ($(wc -l <"$tmp/want") lines)"
