# Blender's cloth modifier on the peers' scenes (bench/peers.sh), headless:
#   blender --background --factory-startup -t 1 --python blender-cloth.py -- \
#     IN.obj OUTDIR|- FRAMES QUALITY MASS TENSION SHEAR BENDING THICKNESS FRICTION CUBE
# IN.obj: the cloth's first frame in drape's y-up frame (vertices in
# drape's node order, drape's triangles); Blender runs z up (x, -z, y).
# One cloth frame is sqrt(0.001) s of simulated time; frame 1 is the
# start, so FRAMES frames after it. Each frame is written back in drape's
# frame and order as OUTDIR/frame-NNNN.obj. Prints the wall seconds of the
# stepping alone (scene.frame_set), not the start-up nor the writing.
import sys
import time

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
src, outdir = argv[0], argv[1]
frames, quality = int(argv[2]), int(argv[3])
mass, tension, shear, bending, thick, mu = (float(a) for a in argv[4:10])
cube = argv[10] == "1"

verts, faces = [], []
with open(src) as f:
    for line in f:
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            x, y, z = (float(a) for a in w[1:4])
            verts.append((x, -z, y))
        elif w[0] == "f":
            faces.append(tuple(int(a.split("/")[0]) - 1 for a in w[1:4]))

scene = bpy.context.scene
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o, do_unlink=True)
scene.gravity = (0, 0, -9.80665)
scene.frame_start = 1
scene.frame_end = frames + 1


def collider(name, lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    q = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    me = bpy.data.meshes.new(name)
    me.from_pydata(v, [], q)
    me.update()
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    ob.modifiers.new("Collision", 'COLLISION')
    ob.collision.thickness_outer = max(thick, 0.001)  # default 20 mm; 1 mm at least
    ob.collision.cloth_friction = mu
    return ob


collider("floor", (-1, -1, -0.1), (1, 1, 0))
if cube:
    collider("cube", (0.02, 0, 0), (0.12, 0.1, 0.1))

me = bpy.data.meshes.new("cloth")
me.from_pydata(verts, [], faces)
me.update()
cloth = bpy.data.objects.new("cloth", me)
scene.collection.objects.link(cloth)
mod = cloth.modifiers.new("Cloth", 'CLOTH')
s = mod.settings
s.quality = quality
s.mass = mass  # per vertex
s.air_damping = 0
s.tension_stiffness = s.compression_stiffness = tension
s.shear_stiffness = shear
s.bending_stiffness = bending
c = mod.collision_settings
c.use_collision = True
c.use_self_collision = True
c.distance_min = thick  # default 15 mm
c.self_distance_min = thick  # default 15 mm
c.friction = mu
mod.point_cache.frame_start = 1
print("cloth: mass %g tension %g shear %g bending %g distance %g self %g quality %d" % (s.mass, s.tension_stiffness, s.shear_stiffness, s.bending_stiffness, c.distance_min, c.self_distance_min, s.quality))
mod.point_cache.frame_end = frames + 1


def write(n):
    dg = bpy.context.evaluated_depsgraph_get()
    ev = cloth.evaluated_get(dg)
    m = ev.to_mesh()
    with open("%s/frame-%04d.obj" % (outdir, n), "w") as f:
        for v in m.vertices:
            x, y, z = v.co
            f.write("v %.9g %.9g %.9g\n" % (x, z, -y))
        for p in faces:
            f.write("f %d %d %d\n" % (p[0] + 1, p[1] + 1, p[2] + 1))
    ev.to_mesh_clear()


wall = 0.0
for n in range(frames + 1):
    t0 = time.perf_counter()
    scene.frame_set(n + 1)
    wall += time.perf_counter() - t0
    if outdir != "-":
        write(n)
print("simulated %.6g s" % (frames * 0.001 ** 0.5))
print("wall time %.3f s" % wall)
