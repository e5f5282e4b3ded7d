# make-ball.py - tests/data/mikk: a low-poly UV sphere and a normal map that
# leans its normals in waves, baked in the tangent frames Blender gives it
# (MikkTSpace: mesh.calc_tangents), read as a glTF renderer reads them (the
# normal and tangent interpolated, the tangent made perpendicular, the
# bitangent sign x n x t), for test_normalmap.c.  From the repository root:
#   blender -b --factory-startup --python-exit-code 1 --python tests/data/mikk/make-ball.py -- tests/data/mikk
import bpy, bmesh, sys, math
sys.path.insert(0, "tests/tools")
from quads import png
out = sys.argv[sys.argv.index("--") + 1]
W, H = 256, 128
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_uv_sphere_add(segments=12, ring_count=6, radius=1, calc_uvs=True)
ob = bpy.context.active_object
bpy.ops.object.shade_smooth()
me = ob.data
bm = bmesh.new(); bm.from_mesh(me)
bmesh.ops.triangulate(bm, faces=bm.faces[:])
bm.to_mesh(me); bm.free()
me.calc_normals_split()
me.calc_tangents()
uvl = me.uv_layers.active.data
tris = []
for p in me.polygons:
    assert p.loop_total == 3
    c = []
    for li in p.loop_indices:
        l = me.loops[li]
        c.append((tuple(me.vertices[l.vertex_index].co), tuple(l.normal), tuple(uvl[li].uv), tuple(l.tangent),
                  l.bitangent_sign))
    tris.append(c)
def sub(a, b): return [a[i] - b[i] for i in range(3)]
def dot(a, b): return sum(a[i] * b[i] for i in range(3))
def cross(a, b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def norm(a):
    l = math.sqrt(dot(a, a)); return [x / l for x in a]
def mix(vals, w): return [sum(w[k] * vals[k][i] for k in range(3)) for i in range(len(vals[0]))]
def wavy(p):
    """The normal the map stands for at p: the sphere's, leaning in waves (6 round, 5 down)."""
    q = norm(p)
    th, ph = math.acos(max(-1, min(1, q[1]))), math.atan2(-q[2], q[0])
    eph = [-math.sin(ph), 0, -math.cos(ph)]
    eth = [math.cos(th) * math.cos(ph), -math.sin(th), -math.cos(th) * math.sin(ph)]
    a, b = 0.6 * math.sin(th) * math.sin(6 * ph), 0.6 * math.sin(th) * math.cos(5 * th)
    return norm([q[i] + a * eph[i] + b * eth[i] for i in range(3)])
img = [[None] * W for _ in range(H)]
best = [[-1e9] * W for _ in range(H)]
for t in tris:
    uv = [c[2] for c in t]
    us = [u * W - 0.5 for u, v in uv]; vs = [(1 - v) * H - 0.5 for u, v in uv]  # texel centres, row 0 at the top
    x0, x1 = max(0, int(min(us)) - 2), min(W - 1, int(max(us)) + 2)
    y0, y1 = max(0, int(min(vs)) - 2), min(H - 1, int(max(vs)) + 2)
    d = (us[1] - us[0]) * (vs[2] - vs[0]) - (us[2] - us[0]) * (vs[1] - vs[0])
    if abs(d) < 1e-12: continue
    for y in range(y0, y1 + 1):
        for x in range(x0, x1 + 1):
            b1 = ((x - us[0]) * (vs[2] - vs[0]) - (us[2] - us[0]) * (y - vs[0])) / d
            b2 = ((us[1] - us[0]) * (y - vs[0]) - (x - us[0]) * (vs[1] - vs[0])) / d
            w = [1 - b1 - b2, b1, b2]
            inside = min(w)
            if inside < best[y][x] or inside < -0.5: continue
            best[y][x] = inside
            w = [max(0.0, k) for k in w]; s = sum(w); w = [k / s for k in w]  # a margin texel: the nearest point
            p = mix([c[0] for c in t], w); n = norm(mix([c[1] for c in t], w))
            tg = mix([c[3] for c in t], w); tg = norm(sub(tg, [n[i] * dot(n, tg) for i in range(3)]))
            bt = [t[0][4] * e for e in cross(n, tg)]
            true = wavy(p)
            c = (dot(true, tg), dot(true, bt), dot(true, n))
            img[y][x] = [max(0, min(255, round((e + 1) / 2 * 255))) for e in c]
rows = [sum((px or [128, 128, 255] for px in r), []) for r in img]
open(out + "/ball_nrm.png", "wb").write(png(W, H, rows))
with open(out + "/ball.obj", "w") as f:
    f.write("# a 12 x 6 UV sphere (Blender 3.4's), its map baked in Blender's MikkTSpace frames\nmtllib ball.mtl\nusemtl ball\n")
    k = 1
    for t in tris:
        for c in t: f.write("v %.6f %.6f %.6f\n" % c[0])
        for c in t: f.write("vt %.6f %.6f\n" % c[2])
        for c in t: f.write("vn %.6f %.6f %.6f\n" % c[1])
        f.write("f %d/%d/%d %d/%d/%d %d/%d/%d\n" % (k, k, k, k + 1, k + 1, k + 1, k + 2, k + 2, k + 2)); k += 3
open(out + "/ball.mtl", "w").write("newmtl ball\nKd 0.8 0.8 0.8\nnorm ball_nrm.png\n")
print("TRIS", len(tris))
