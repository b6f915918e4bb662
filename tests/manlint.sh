#!/usr/bin/env bash
# manlint.sh: the three manual pages are clean (issue 30: man -l
# man/drape-replay.5 printed 59 troff warnings): mandoc -T lint reports no
# warning or error, and, where man(1) is there, groff formats each at 80
# columns without a warning (a column table too wide for the page wrapped
# word by word at its right edge). Skipped (77) without mandoc (Debian:
# apt-get install mandoc; .ci/setup installs it).
set -u

srcdir=${srcdir:-$(cd "$(dirname "$0")/.." && pwd)}
command -v mandoc >/dev/null 2>&1 || { echo "mandoc not found: skipped"; exit 77; }
failed=0
for page in man/drape.1 man/drape-scene.5 man/drape-replay.5; do
	# STYLE notes (a manual not installed here, a long source line) are
	# not warnings
	out=$(mandoc -T lint -W warning "$srcdir/$page" 2>&1)
	if [ -n "$out" ]; then
		echo "FAIL: mandoc -T lint $page:"
		echo "$out"
		failed=1
	fi
	if command -v man >/dev/null 2>&1 && command -v groff >/dev/null 2>&1; then
		out=$(MANWIDTH=80 man -l "$srcdir/$page" 2>&1 >/dev/null)
		if [ -n "$out" ]; then
			echo "FAIL: man -l $page at 80 columns:"
			echo "$out" | head -n 5
			failed=1
		fi
	fi
	[ $failed -eq 0 ] && echo "ok: $page"
done
exit $failed
