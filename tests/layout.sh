#!/usr/bin/env bash
# layout.sh: README.md's Layout against the source tree. The list of
# headers between the "layout:" markers is made from each src/*.h's first
# line (`/* NAME.h: what it is`), one line a header, in name order; the
# check fails when a header present now is missing from it, when a line
# differs from its header's first line, or when it lists a header that is
# gone, and when a man page of man/ is not named in the Layout section.
#   tests/layout.sh            check (make check runs it)
#   tests/layout.sh --write    rewrite the block in README.md (make layout)
set -u

srcdir=${srcdir:-.}
readme=$srcdir/README.md
begin='<!-- layout: begin (make layout writes this list from each header'"'"'s first line) -->'
end='<!-- layout: end -->'

# the generated lines: "    src/NAME.h: description", the header's first
# line without its "/* " and " */"; a comment that goes on is marked " ..."
generate() {
	local h n line
	for h in "$srcdir"/src/*.h; do
		n=${h##*/}
		IFS= read -r line <"$h" || line=
		case $line in
		"/* $n: "*) line=${line#"/* $n: "} ;;
		*) line="(its first line is not /* $n: what it is)" ;;
		esac
		case $line in
		*' */') line=${line% \*/} ;;
		*) line="$line ..." ;;
		esac
		printf '    src/%s: %s\n' "$n" "$line"
	done
}

# README.md with the block between the markers replaced by stdin
replace() {
	awk -v b="$begin" -v e="$end" -v f="$1" '
		$0 == b { print; print ""; while ((getline l < f) > 0) print l; print ""; skip = 1; next }
		$0 == e { skip = 0 }
		!skip' "$readme"
}

tmp=$(mktemp -d /tmp/drape-layout-XXXXXX) || exit 1
trap 'rm -rf "$tmp"' EXIT
generate >"$tmp/layout"
[ -s "$tmp/layout" ] || { echo "FAIL: no header found in $srcdir/src"; exit 1; }
grep -qxF "$begin" "$readme" && grep -qxF "$end" "$readme" ||
	{ echo "FAIL: README.md has no Layout markers ($begin ... $end)"; exit 1; }

if [ "${1:-}" = --write ]; then
	replace "$tmp/layout" >"$tmp/README.md" && cat "$tmp/README.md" >"$readme" || exit 1
	echo "README.md: Layout written ($(wc -l <"$tmp/layout") headers)"
	exit 0
fi

fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
awk -v b="$begin" -v e="$end" '$0 == e { on = 0 } on && NF { print } $0 == b { on = 1 }' \
	"$readme" >"$tmp/listed"
for h in "$srcdir"/src/*.h; do
	n=${h##*/}
	want=$(grep -F "    src/$n: " "$tmp/layout")
	got=$(grep -F "    src/$n: " "$tmp/listed")
	case $want in *": (its first line is not"*) fail "src/$n: its first line is not /* $n: what it is"; continue ;; esac
	if [ -z "$got" ]; then
		fail "src/$n is not in README.md's Layout"
	elif [ "$got" != "$want" ]; then
		fail "src/$n: README.md's Layout says '$got', its first line '$want'"
	fi
done
while IFS= read -r l; do
	n=${l#    src/}
	n=${n%%: *}
	[ -f "$srcdir/src/$n" ] || fail "README.md's Layout lists src/$n, which is not there"
done <"$tmp/listed"
# the man pages, by name(section), in the Layout section
sed -n '/^## Layout/,/^## /p' "$readme" >"$tmp/section"
for m in "$srcdir"/man/*.[1-9]; do
	n=${m##*/}
	page="${n%.*}(${n##*.})"
	grep -qF "$page" "$tmp/section" || fail "man/$n: $page is not named in README.md's Layout"
done
if [ "$fails" -gt 0 ]; then
	echo "$fails problem(s): run 'make layout' (tests/layout.sh --write from the source tree)"
	echo "to write the Layout from the headers' first lines, and commit README.md"
	exit 1
fi
echo "ok: README.md's Layout lists the $(wc -l <"$tmp/layout") headers of src/ by their first lines"
