# drape_import.py: a drape export opened in Blender, its frames on
# Blender's. Run as
#   blender --python drape_import.py -- REST.obj CLOTH.pc2 [--obstacles OBS.obj] [--fps F]
# with the files of `drape export --obj REST.obj --pc2 CLOTH.pc2
# [--obstacles OBS.obj] [--fps F]` (F as given there; drape's default is
# its output rate, 50 frames a second). It imports the cloth with the OBJ
# importer's defaults (y up made z up in the object's transform), puts a
# Mesh Cache on it whose first sample is the scene's first frame (Blender
# starts at frame 1, the modifier at 0: drape's first frame would be
# skipped), sets the scene's rate to F and its last frame to the last
# sample, so that it plays at real time, and imports the obstacles.
import struct
import sys

import bpy


def pc2_samples(path):
    with open(path, "rb") as f:
        head = f.read(32)
    if len(head) != 32 or head[:12] != b"POINTCACHE2\0":
        raise ValueError("%s: not a PC2 file" % path)
    return struct.unpack("<i", head[28:32])[0]


def imported(path):
    before = set(bpy.data.objects)
    bpy.ops.wm.obj_import(filepath=path)
    return [o for o in bpy.data.objects if o not in before]


def load(rest, pc2, obstacles=None, fps=50.0):
    """The cloth object, its Mesh Cache set on the scene's frames."""
    scene = bpy.context.scene
    cloth = imported(rest)[0]
    cloth.name = "drape cloth"
    for p in cloth.data.polygons:
        p.use_smooth = True
    mod = cloth.modifiers.new("drape", 'MESH_CACHE')
    mod.cache_format = 'PC2'
    mod.filepath = pc2
    mod.frame_start = scene.frame_start
    # Blender's rate is an integer over a base: F = fps / fps_base
    scene.render.fps = max(1, round(fps))
    scene.render.fps_base = scene.render.fps / fps
    scene.frame_end = scene.frame_start + pc2_samples(pc2) - 1
    if obstacles:
        imported(obstacles)
    return cloth


def main(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    obstacles, fps, files = None, 50.0, []
    while args:
        a = args.pop(0)
        if a == "--obstacles" and args:
            obstacles = args.pop(0)
        elif a == "--fps" and args:
            fps = float(args.pop(0))
        else:
            files.append(a)
    if len(files) != 2 or not fps > 0:
        sys.stderr.write("usage: blender --python drape_import.py -- REST.obj CLOTH.pc2 "
                         "[--obstacles OBS.obj] [--fps F]\n")
        sys.exit(2)
    load(files[0], files[1], obstacles, fps)


if __name__ == "__main__":
    main(sys.argv)
