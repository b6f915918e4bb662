#!/bin/sh
# boundary.sh: the includes that would let a module see another's state
# fail make check.
# - stepper.h, the one way into a run, includes no project header but
#   integrate.h (for enum integrator_kind): what it names by pointer is
#   declared, so that its callers see neither the stages nor their state;
# - the stepper's stages (collide.h, contacts.h, pbd.h, bdf2.h,
#   implicit.h) are included by the stepper and the stages alone, and by
#   tests/test_collide.c, which drives the collision stages directly;
# - a module's private header, src/NAME_impl.h, is included by its own
#   files (src/NAME.c, src/NAME_*.c) alone, and by the white-box tests
#   listed below.
set -u
srcdir=${srcdir:-.}
cd "$srcdir" || exit 1
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# the project headers a file includes, one a line
includes() { sed -n 's/^#include "\([^"]*\)".*/\1/p' "$1"; }

for h in $(includes src/stepper.h); do
	case $h in
	integrate.h) ;;
	*) fail "src/stepper.h includes $h: declare what it names instead (struct NAME;)" ;;
	esac
done

stages='collide.h contacts.h pbd.h bdf2.h implicit.h'
for f in src/*.c src/*.h tests/*.c tests/*.h tests/fuzz/*.c; do
	for h in $(includes "$f"); do
		case " $stages " in
		*" $h "*)
			case $f in
			src/stepper.c | src/collide*.[ch] | src/contacts.c | src/pbd.c | \
			    src/bdf2.c | src/implicit.c | tests/test_collide.c) ;;
			*) fail "$f includes $h, a stage of the stepper: use stepper.h" ;;
			esac ;;
		esac
		case $h in
		*_impl.h)
			mod=${h%_impl.h}
			case $f:$h in
			src/"$mod".c:* | src/"$mod"_*.c:* | src/"$mod"_*.h:*) ;;
			# white-box: the held pairs and flat patches of bvh
			tests/test_collide.c:broad_impl.h) ;;
			*) fail "$f includes $h, private to src/$mod*.c" ;;
			esac ;;
		esac
	done
done

[ "$fails" -eq 0 ] || exit 1
echo "ok: the headers' boundaries hold"
