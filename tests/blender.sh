#!/usr/bin/env bash
# blender.sh: Blender as a real client of drape export. A small replay's
# PC2 and rest OBJ are opened in Blender headless (bpy) as drape(1) says
# to (the OBJ importer's defaults put the y-up change in the object's
# transform; the Mesh Cache modifier keeps its default axes), and the
# evaluated mesh of three frames must equal drape's own OBJ of each frame.
# Then an export at 24 frames a second with its obstacles, through the
# shipped blender/drape_import.py: scene frame 1 is drape's first frame.
# Skipped (77) where blender is not installed: it is 600 MB, not a build
# dependency (Debian: apt-get install --no-install-recommends blender).
set -u

DRAPE=${DRAPE:-src/drape}
srcdir=${srcdir:-.}
command -v blender >/dev/null 2>&1 || { echo "blender not found: skipped"; exit 77; }

tmp=$(mktemp -d /tmp/drape-blender-XXXXXX) || exit 1
trap 'rm -rf "$tmp"' EXIT

cat >"$tmp/fall.scene" <<'SCENE'
[simulation]
duration = 50 ms
output_rate = 200 Hz
[cloth]
nodes = 6 6
spacing = 10 mm
origin = 0 5 0 mm
orientation = +x +z
weight = 150 g/m2
thickness = 0.55 mm
modulus_warp = 0.45 MPa
modulus_weft = 0.30 MPa
shear_modulus = 9 kPa
bending_warp = 3 uN*m
bending_weft = 2 uN*m
velocity = 0 -0.3 0 m/s
[plane]
point = 0 0 0 m
SCENE

"$DRAPE" run --headless --record "$tmp/fall.drr" "$tmp/fall.scene" >/dev/null &&
	"$DRAPE" export --pc2 "$tmp/fall.pc2" --obj "$tmp/rest.obj" --obj-seq "$tmp/seq" \
		"$tmp/fall.drr" || { echo "FAIL: drape could not record and export"; exit 1; }
frames=$(ls "$tmp/seq" | wc -l)
[ "$frames" -eq 11 ] || { echo "FAIL: $frames frames exported, expected 11"; exit 1; }
blender --background --factory-startup -t 1 --python "$srcdir/tests/blender_check.py" -- \
	"$tmp/rest.obj" "$tmp/fall.pc2" "$tmp/seq" 0 5 10 >"$tmp/out" 2>&1
rc=$?
grep '^frame ' "$tmp/out"
if [ $rc -ne 0 ] || [ "$(grep -c 'vertices equal$' "$tmp/out")" -ne 3 ]; then
	echo "FAIL: Blender's frames are not drape's (exit $rc):"
	tail -n 20 "$tmp/out"
	exit 1
fi

# issue 30: through the shipped import script, at Blender's 24 frames a
# second: scene frame 1 is drape's first (the Mesh Cache starts at 0,
# Blender's scenes at 1), the grid's texture coordinates, the obstacles
"$DRAPE" export --fps 24 --pc2 "$tmp/fall24.pc2" --obj "$tmp/rest24.obj" \
	--obj-seq "$tmp/seq24" --obstacles "$tmp/obstacles.obj" "$tmp/fall.drr" ||
	{ echo "FAIL: drape export --fps 24"; exit 1; }
samples=$(ls "$tmp/seq24" | wc -l)
# 50 ms at 24 a second: the samples at 0, 1/24 s and 2/24 s
[ "$samples" -eq 2 ] || { echo "FAIL: $samples samples at 24 a second, expected 2"; exit 1; }
blender --background --factory-startup -t 1 --python "$srcdir/tests/blender_import_check.py" -- \
	"$srcdir/blender" "$tmp/rest24.obj" "$tmp/fall24.pc2" "$tmp/obstacles.obj" "$tmp/seq24" \
	24 "$samples" plane_17 0 1 >"$tmp/out" 2>&1
rc=$?
grep -E '^(ok|FAIL):' "$tmp/out"
if [ $rc -ne 0 ] || grep -q '^FAIL:' "$tmp/out" || [ "$(grep -c '^ok:' "$tmp/out")" -ne 8 ]; then
	echo "FAIL: the import script (exit $rc):"
	tail -n 20 "$tmp/out"
	exit 1
fi
echo "all passed"
