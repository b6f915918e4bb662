# blender_import_check.py: run by tests/blender.sh inside Blender (bpy).
# Loads a drape export with the shipped blender/drape_import.py and checks
# what it promises: scene frame 1 is drape's first frame (and frame 1 + k
# its k-th, compared exactly with drape's OBJ of it), the scene plays at
# the export's rate to its last sample, the cloth has the grid's texture
# coordinates, and the obstacles are there by name.
# Arguments: DIR-OF-drape_import.py REST.obj CLOTH.pc2 OBSTACLES.obj SEQ
# FPS SAMPLES OBSTACLE-NAME FRAME... Exits 1 with the first difference.
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
sys.path.insert(0, args[0])
import drape_import  # noqa: E402

rest, pc2, obstacles, seq = args[1], args[2], args[3], args[4]
fps, samples, obstacle = float(args[5]), int(args[6]), args[7]
frames = [int(a) for a in args[8:]]
bad = 0


def say(ok, what):
    global bad
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok:
        bad = 1


def drape_frame(k):
    with open("%s/frame_%05d.obj" % (seq, k)) as f:
        return [tuple(float(c) for c in line.split()[1:4])
                for line in f if line.startswith("v ")]


bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
cloth = drape_import.load(rest, pc2, obstacles, fps)
say(scene.frame_start == 1, "the scene starts at frame %d" % scene.frame_start)
say(scene.frame_end == samples, "the scene ends at frame %d, %d samples"
    % (scene.frame_end, samples))
rate = scene.render.fps / scene.render.fps_base
say(abs(rate - fps) < 1e-9 * fps, "the scene plays %.9g frames a second" % rate)
uv = cloth.data.uv_layers.active
say(uv is not None, "the cloth has texture coordinates")
if uv is not None:
    us = [d.uv[0] for d in uv.data]
    vs = [d.uv[1] for d in uv.data]
    say(min(us) == 0 and max(us) == 1 and min(vs) == 0 and max(vs) == 1,
        "they span 0 to 1: u %g to %g, v %g to %g" % (min(us), max(us), min(vs), max(vs)))
say(obstacle in bpy.data.objects, "the obstacle %s is imported (%s)"
    % (obstacle, ", ".join(o.name for o in bpy.data.objects)))
for k in frames:
    scene.frame_set(1 + k)
    dg = bpy.context.evaluated_depsgraph_get()
    ev = cloth.evaluated_get(dg)
    me = ev.to_mesh()
    got = [tuple(v.co) for v in me.vertices]
    ev.to_mesh_clear()
    want = drape_frame(k)
    diff = [i for i in range(len(want)) if i >= len(got) or got[i] != want[i]]
    say(len(got) == len(want) and not diff, "scene frame %d is drape's frame %d%s"
        % (1 + k, k, "" if not diff else ": vertex %d differs" % diff[0]))
sys.stdout.flush()
sys.exit(bad)
