# blender_check.py: run by tests/blender.sh inside Blender (bpy). Opens
# drape's rest OBJ and PC2 as drape(1) advises (the OBJ importer's
# defaults, the Mesh Cache modifier's defaults), and compares the evaluated
# mesh of each given frame with drape's own OBJ of that frame, exactly.
# Exits 1 on a difference, with the first one.
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
rest, pc2, seq = args[0], args[1], args[2]
frames = [int(a) for a in args[3:]]


def drape_frame(k):
    with open("%s/frame_%05d.obj" % (seq, k)) as f:
        return [tuple(float(c) for c in line.split()[1:4])
                for line in f if line.startswith("v ")]


bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=rest)
ob = bpy.context.selected_objects[0]
mod = ob.modifiers.new("drape", 'MESH_CACHE')
mod.cache_format = 'PC2'
mod.filepath = pc2
bad = 0
for k in frames:
    bpy.context.scene.frame_set(k)
    dg = bpy.context.evaluated_depsgraph_get()
    ev = ob.evaluated_get(dg)
    me = ev.to_mesh()
    got = [tuple(v.co) for v in me.vertices]
    ev.to_mesh_clear()
    want = drape_frame(k)
    if len(got) != len(want):
        print("frame %d: %d vertices in Blender, %d in drape" % (k, len(got), len(want)))
        bad = 1
        continue
    # float32 both ways: equal, not near
    diff = [i for i in range(len(got)) if got[i] != want[i]]
    if diff:
        i = diff[0]
        print("frame %d: %d vertices differ; vertex %d: Blender %r, drape %r"
              % (k, len(diff), i, got[i], want[i]))
        bad = 1
    else:
        print("frame %d: %d vertices equal" % (k, len(got)))
sys.stdout.flush()
sys.exit(bad)
