#!/usr/bin/env python3
"""randscene.py - random scene files drawn from the whole grammar of docs/scene.md.

    randscene.py SEED DIR      writes DIR/scene-SEED.scene (and the textures and
                               models it names, once, into DIR)

Every directive and key of the format appears with some probability (both
spellings of centre/center and colour/color, a byte-order mark): camera
by lookat or by angles, with zoom or fov (a pinhole, perhaps with aperture and
focus), ortho or fisheye, and roll; ambient, background; every
settings key and value (depth, cutoff, fresnel, glass_shadows,
rough_samples, lens_samples, exposure, the four texture filters, the
sampling and what the depth limit returns among them; the path integrator
in a quarter of the scenes, some with clamp_indirect, filter_glossy or caustics, a view transform
(tonemap) in some, adaptive sampling's contrast, the area
lights' light_samples and denoising in some); textures (PPM
P3/P6, PGM P2/P5, PNG, JPEG, smooth or closest, wrapping each axis its way); materials with and without specular
and textures, mirrors (reflect, roughness, some with a rim, reflect_edge), dielectrics (ior, transmit,
absorb; some with a mirror share, reflect, some frosted, roughness), clear coats (coat, coat_roughness) and emission, on any primitive; a model whose MTL gives
one material a texture (map_Kd with -s and -o), a cutout (map_d) and a height map (bump), the other a normal map (norm), one with vertex colours
and no materials, and a GLB with its texture embedded (and one whose image is also its normal map,
emission, metal-roughness and occlusion texture, and one of alphaMode BLEND whose image's alpha
runs from holes to whole), and Blender's glTF of a lit scene whose instances take its
lights and camera (`lights`, `camera`); lamps (an emissive
sphere at a light); spheres, planes (with and
without their texture mapping keys) and triangles (with normals and uv); models from OBJ (with and without smooth, each builder) and from
.tmd (converted by the caller as DIR/mesh.tmd); instances with transforms and
material overrides; point, spot, directional, sphere and rect lights with position,
target, direction, soft, attenuate, colour and intensity; an environment
(a .hdr sky with a sun, or a PNG, some strength and turn).  Numbers are drawn
with many digits, so that values that are normalised, converted or derived
differ in their last bits when they take another path.

The property test (tests/cli/randscene.sh) renders each scene standalone
and through a server with two clients, and compares the frames bit for bit.
"""
import os
import random
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gltftex  # noqa: E402  (the textured quad as a GLB)
import envmap  # noqa: E402  (a sky panorama with a sun)


def num(r, lo, hi):
    """A number with up to 9 significant digits, or a short one."""
    v = r.uniform(lo, hi)
    # half of them short, as people write them (whole numbers, one decimal)
    short = round(v, r.choice([0, 1]))
    if r.random() < 0.5 and lo <= short <= hi and (lo < 0 or short > 0):
        v = short
    return "%.9g" % v


def vec(r, lo, hi):
    return " ".join(num(r, lo, hi) for _ in range(3))


def colour(r, hi=1.0):
    return vec(r, 0.0, hi)


def direction(r):
    """A non-zero direction, not normalised (as people write them)."""
    while True:
        v = [float(num(r, -2, 2)) for _ in range(3)]
        if sum(x * x for x in v) > 0.05:
            return " ".join("%.9g" % x for x in v)


def write_assets(d):
    """Textures and models every scene may name; written once per directory."""
    rng = random.Random(12345)
    if not os.path.exists(os.path.join(d, "sky.hdr")):
        envmap.write_hdr(os.path.join(d, "sky.hdr"), 32, 16, envmap.sky(0.3, 0.25, 0.2, 60.0))
    if not os.path.exists(os.path.join(d, "t6.ppm")):
        with open(os.path.join(d, "t6.ppm"), "wb") as f:
            f.write(b"P6\n7 5\n255\n" + bytes(rng.randrange(256) for _ in range(7 * 5 * 3)))
        with open(os.path.join(d, "t3.ppm"), "w") as f:
            f.write("P3\n3 4\n15\n" + " ".join(str(rng.randrange(16)) for _ in range(3 * 4 * 3)) + "\n")
        with open(os.path.join(d, "t5.pgm"), "wb") as f:
            f.write(b"P5\n4 4\n255\n" + bytes(rng.randrange(256) for _ in range(16)))
        with open(os.path.join(d, "t2.pgm"), "w") as f:
            f.write("P2\n2 3\n9\n" + " ".join(str(rng.randrange(10)) for _ in range(6)) + "\n")
    if not os.path.exists(os.path.join(d, "quad.glb")):
        data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "textured")
        shutil.copy(os.path.join(data, "quadrants.png"), os.path.join(d, "tq.png"))
        shutil.copy(os.path.join(data, "quadrants.jpg"), os.path.join(d, "tq.jpg"))
        sampler = {"magFilter": 9728} if rng.random() < 0.5 else None
        png = open(os.path.join(data, "quadrants.png"), "rb").read()
        gltftex.write_glb(os.path.join(d, "quad.glb"), png, "image/png", sampler)
        # the same with the image as its normal map, emission, metal-roughness and occlusion texture too
        gltftex.write_glb(os.path.join(d, "maps.glb"), png, "image/png", sampler, maps=True)
        # alphaMode BLEND over a 4 x 4 image whose alpha runs from none (holes) to whole
        from quads import png as make_png
        rgba = make_png(4, 4, [sum(([rng.randrange(256) for _ in range(3)] + [(85 * (x + y)) % 256]
                                    for x in range(4)), []) for y in range(4)], 6)
        gltftex.write_glb(os.path.join(d, "blend.glb"), rgba, "image/png", sampler, blend=True)
    if not os.path.exists(os.path.join(d, "lit.glb")):  # Blender's scene with its point lamp, sun and camera
        here = os.path.dirname(os.path.abspath(__file__))
        shutil.copy(os.path.join(here, "..", "data", "gltf", "lit.glb"), os.path.join(d, "lit.glb"))
    if not os.path.exists(os.path.join(d, "mesh.obj")):
        # a bumpy 6x6 grid with texture coordinates, two materials, normals on one half
        n = 6
        lines = ["mtllib mesh.mtl"]
        for j in range(n + 1):
            for i in range(n + 1):
                lines.append("v %.9g %.9g %.9g" % (i / n - 0.5, rng.uniform(-0.15, 0.15), j / n - 0.5))
                lines.append("vt %.9g %.9g" % (i / n * 2, j / n * 2))
                lines.append("vn %.9g 1 %.9g" % (rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)))
        for j in range(n):
            lines.append("usemtl %s" % ("shiny" if j < n // 2 else "matte"))
            for i in range(n):
                a = j * (n + 1) + i + 1
                b, c, e = a + 1, a + n + 2, a + n + 1
                if i < n // 2:
                    lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, b, b, b, c, c, c))
                    lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, c, c, c, e, e, e))
                else:
                    lines.append("f %d/%d %d/%d %d/%d %d/%d" % (a, a, b, b, c, c, e, e))
        with open(os.path.join(d, "mesh.obj"), "w") as f:
            f.write("\n".join(lines) + "\n")
        with open(os.path.join(d, "mesh.mtl"), "w") as f:
            # the model's own texture (MTL map_Kd, carried in its .tmd), placed by -s and -o;
            # a ray-traced reflection (illum 3: a mirror of Ks) and an emission (Ke), carried too;
            # the matte half a cutout (map_d: a random grey mask, holes under half), half the
            # triangles, so that a SIMD path walks them apart from the wide tree; the shiny
            # half normal-mapped (norm: a random image's texels as normals, half tilted), the
            # matte half bumped by the grey mask as a height map (what older builds leave out)
            bump = "" if os.environ.get("LANRAY_RANDSCENE_WHITTED") else "bump -bm 0.03 t5.pgm\n"
            f.write("newmtl shiny\nKd 0.7 0.6 0.2\nKs 0.5 0.5 0.5\nNs 33\nillum 3\nnorm -bm 0.5 t6.ppm\n"
                    "newmtl matte\nKd 0.2 0.5 0.7\n"
                    "Ke 0.05 0.1 0.05\nmap_Kd -s 0.75 1.5 1 -o 0.1 0.2 t6.ppm\nmap_d t5.pgm\n" + bump)
    if not os.path.exists(os.path.join(d, "painted.obj")):
        # a bumpy 5x5 grid with vertex colours and no materials (some in the x y z w r g b form)
        n = 5
        lines = []
        for j in range(n + 1):
            for i in range(n + 1):
                w = " 1" if (i + j) % 3 == 0 else ""
                lines.append("v %.9g %.9g %.9g%s %.6g %.6g %.6g" % (i / n - 0.5, rng.uniform(-0.2, 0.2), j / n - 0.5, w,
                                                                   rng.random(), rng.random(), rng.random()))
        for j in range(n):
            for i in range(n):
                a = j * (n + 1) + i + 1
                lines.append("f %d %d %d %d" % (a, a + 1, a + n + 2, a + n + 1))
        with open(os.path.join(d, "painted.obj"), "w") as f:
            f.write("\n".join(lines) + "\n")


def scene(seed):
    r = random.Random(seed)
    out = ["# random scene, seed %d (tests/tools/randscene.py)" % seed]
    cam = ["camera position", vec(r, -6, 6)]
    if r.random() < 0.6:
        cam += ["lookat", vec(r, -1, 1)]
    else:
        cam += ["yaw", num(r, -180, 180), "pitch", num(r, -60, 60)]
    if r.random() < 0.4:
        cam += ["roll", num(r, -45, 45)]
    z = r.random()
    if z < 0.3:
        cam += ["fov", num(r, 20, 120)]
    elif z < 0.6:
        cam += ["zoom", num(r, 0.5, 3)]
    elif z < 0.7:
        cam += ["ortho", num(r, 1, 12)]
    elif z < 0.8:
        cam += ["fisheye", num(r, 30, 360)]
    if z < 0.6 and r.random() < 0.25:  # a pinhole with a lens
        cam += ["aperture", num(r, 0, 0.5), "focus", num(r, 1, 10)]
    out.append(" ".join(cam))
    if r.random() < 0.7:
        out.append("ambient " + colour(r, 0.3))
    if r.random() < 0.7:
        out.append("background " + colour(r, 0.5))
    # sampling is always set: lanray-render and a server default differently
    # (a still image is anti-aliased), and the test compares the two
    st = [r.choice(["aa", "adaptive"]), str(r.choice([1, 1, 2, 3]))]
    if r.random() < 0.4:
        st += ["shading", r.choice(["phong", "diffuse"])]
    if r.random() < 0.4:
        st += ["shadows", r.choice(["on", "off"])]
    if r.random() < 0.5:
        st += ["filter", r.choice(["nearest", "bilinear", "trilinear", "anisotropic"])]
    if r.random() < 0.4:
        st += ["sampling", r.choice(["budget", "product"])]
    if r.random() < 0.4:
        st += ["depth_limit", r.choice(["black", "background", "ambient", "local"])]
    if r.random() < 0.3:
        st += ["depth", str(r.choice([0, 1, 2, 5]))]
    if r.random() < 0.3:
        st += ["cutoff", num(r, 0, 0.5)]
    if r.random() < 0.3:
        st += ["fresnel", r.choice(["exact", "schlick"])]
    if r.random() < 0.3:
        st += ["glass_shadows", r.choice(["tinted", "opaque"])]
    st += ["rough_samples", str(r.choice([1, 2])), "lens_samples", str(r.choice([1, 2]))]  # the defaults (4) are slow for a test
    if r.random() < 0.25:
        st += ["exposure", num(r, -2, 2)]
    if r.random() < 0.3:  # the programs' --width/--height override these
        st += ["width", str(r.randrange(1, 2000)), "height", str(r.randrange(1, 2000))]
    # the integrator from a draw of its own, so that the rest of the scene
    # is what it was before the path integrator (tests/tools/samepixels.sh
    # compares with older builds: LANRAY_RANDSCENE_WHITTED=1 leaves it out)
    newer = not os.environ.get("LANRAY_RANDSCENE_WHITTED")  # what older builds do not read
    if newer and random.Random(seed * 7919 + 31).random() < 0.25:
        st += ["integrator", "path"]
        extra = random.Random(seed * 7919 + 37)
        if extra.random() < 0.5:
            st += ["emitter_sampling", extra.choice(["mis", "nee", "bsdf"])]
        if extra.random() < 0.3:
            st += ["roulette", str(extra.choice([0, 1, 3, 8]))]
        held = random.Random(seed * 7919 + 97)  # Clamp Indirect, a draw of its own (older builds refuse it)
        if held.random() < 0.3:
            st += ["clamp_indirect", num(held, 0.05, 20)]
        blur = random.Random(seed * 7919 + 103)  # Filter Glossy, a draw of its own (older builds refuse it)
        if blur.random() < 0.4:
            st += ["filter_glossy", num(blur, 0.05, 10)]
        kept = random.Random(seed * 7919 + 107)  # the caustics kept, a draw of its own (older builds refuse it)
        if kept.random() < 0.3:
            st += ["caustics", kept.choice(["both", "reflective", "refractive", "none"])]
    if newer and random.Random(seed * 7919 + 41).random() < 0.3:  # adaptive sampling's colour threshold
        st += ["contrast", str(random.Random(seed * 7919 + 43).choice([0, 8, 40, 255]))]
    if newer and random.Random(seed * 7919 + 59).random() < 0.25:  # the frame filtered by its pixels' guides
        st += ["denoise", "on"]
    view = random.Random(seed * 7919 + 101)  # a view transform, a draw of its own (older builds refuse it)
    if newer and view.random() < 0.2:
        st += ["tonemap", view.choice(["none", "aces", "neutral"])]
    if newer and random.Random(seed * 7919 + 47).random() < 0.2:  # every area light's points, the view's
        st += ["light_samples", str(random.Random(seed * 7919 + 53).choice([1, 2, 5]))]
    if st:
        out.append("settings " + " ".join(st))

    textures = []
    for i in range(r.choice([0, 0, 1, 2])):
        name = "tex%d" % i
        t = "texture %s %s" % (name, r.choice(["t6.ppm", "t3.ppm", "t5.pgm", "t2.pgm", "tq.png", "tq.jpg"]))
        out.append(t + r.choice(["", "", " closest", " smooth"]) +
                   r.choice(["", "", " wrap clamp", " wrap mirror", " wrap mirror clamp", " wrap repeat mirror"]))
        textures.append(name)
    materials = ["default"]
    for i in range(r.randrange(0, 4)):
        name = "m%d" % i
        m = ["material", name]
        if r.random() < 0.8:
            m += ["diffuse", colour(r)]
        if r.random() < 0.5:
            m += ["specular", colour(r), "shininess", num(r, 0, 120)]
        if textures and r.random() < 0.6:
            m += ["texture", r.choice(textures)]
        z = r.random()
        if z < 0.25:  # a mirror, or a metal, perhaps rough
            m += ["reflect", colour(r)]
            if r.random() < 0.4:
                m += ["roughness", num(r, 0, 1)]
            rim = random.Random(seed * 7919 + 73 + i)  # a rim, a draw of its own (older builds refuse it)
            if newer and rim.random() < 0.4:
                m += ["reflect_edge", colour(rim)]
        elif z < 0.5:  # a dielectric: glass, coloured or absorbing
            m += ["ior", num(r, 1.1, 2.4)]
            if r.random() < 0.5:
                m += ["transmit", colour(r)]
            if r.random() < 0.5:
                m += ["absorb", colour(r, 2)]
            coat = random.Random(seed * 7919 + 59 + i)  # a draw of its own: older builds refuse the pair
            if newer and coat.random() < 0.3:  # a mirror share over the glass
                m += ["reflect", colour(coat, 0.6)]
            frost = random.Random(seed * 7919 + 67 + i)  # frosted glass, a draw of its own (older builds refuse it)
            if newer and frost.random() < 0.3:
                m += ["roughness", num(frost, 0.05, 0.8)]
        if r.random() < 0.15:
            m += ["emit", colour(r)]
        varnish = random.Random(seed * 7919 + 61 + i)  # a clear coat, a draw of its own (older builds refuse it)
        if newer and not 0.25 <= z < 0.5 and varnish.random() < 0.3:  # over anything but a dielectric
            m += ["coat", num(varnish, 0.2, 1)]
            if varnish.random() < 0.6:
                m += ["coat_roughness", num(varnish, 0, 0.8)]
        extra = random.Random(seed * 7919 + 41 + i)  # a draw of its own, as the integrator's
        if newer and extra.random() < 0.2:  # a checker pattern, solid or on the texture coordinates
            m += ["checker", colour(extra), "checker_size", num(extra, 0.05, 2)]
            if extra.random() < 0.5:
                m += ["checker_uv"]
        out.append(" ".join(m))
        materials.append(name)

    def mat():
        return ["material", r.choice(materials)] if r.random() < 0.8 else []

    for _ in range(r.randrange(0, 4)):
        out.append(" ".join(["sphere", r.choice(["centre", "center"]), vec(r, -2, 2), "radius", num(r, 0.1, 1.2)] + mat()))
    for _ in range(r.choice([0, 1, 1, 2])):
        pl = ["plane point", vec(r, -1.5, 0), "normal", direction(r)]
        if r.random() < 0.4:
            pl += ["uvscale", num(r, 0.2, 3)]
        if r.random() < 0.4:
            pl += ["uvrotate", num(r, -90, 90)]
        out.append(" ".join(pl + mat()))
    for _ in range(r.randrange(0, 4)):
        t = ["triangle vertices", " ".join(vec(r, -2, 2) for _ in range(3))]
        if r.random() < 0.4:
            t += ["normals", " ".join(direction(r) for _ in range(3))]
        if r.random() < 0.5:
            t += ["uv", " ".join(num(r, -1, 2) for _ in range(6))]
        out.append(" ".join(t + mat()))
    models, lit = [], []
    for i in range(r.choice([0, 0, 1, 2])):
        name = "mod%d" % i
        takes = random.Random(seed * 7919 + 83 + i)  # a draw of its own: a glTF's lights and camera
        if newer and takes.random() < 0.1:
            m = ["model", name, "lit.glb"]
            lit.append(name)
        elif r.random() < 0.15:
            m = ["model", name, "maps.glb" if r.random() < 0.5 else "quad.glb"]
            if newer and random.Random(seed * 7919 + 79 + i).random() < 0.3:  # a draw of its own
                m[2] = "blend.glb"
        elif r.random() < 0.2:
            m = ["model", name, "painted.obj"]
            if r.random() < 0.5:
                m += ["smooth"]
        elif r.random() < 0.3:
            m = ["model", name, "mesh.tmd"]
            if r.random() < 0.5:
                m += ["bvh", r.choice(["sbt", "mst", "sah"])]
        else:
            m = ["model", name, "mesh.obj"]
            if r.random() < 0.7:
                m += ["bvh", r.choice(["sbt", "mst", "sah"])]
            if r.random() < 0.5:
                m += ["smooth"]
        out.append(" ".join(m))
        models.append(name)
    for name in models:
        for _ in range(r.randrange(1, 3)):
            ins = ["instance", name]
            if r.random() < 0.8:
                ins += ["translate", vec(r, -1.5, 1.5)]
            if r.random() < 0.6:
                ins += ["rotate", vec(r, -180, 180)]
            if r.random() < 0.6:
                ins += ["scale", num(r, 0.3, 2.5)]
            if r.random() < 0.3:
                ins += mat()
            if name in lit:  # its lamps, and perhaps its view (the scene's camera line then replaced)
                ins += ["lights"] + (["camera"] if random.Random(seed * 7919 + 89).random() < 0.5 else [])
            out.append(" ".join(ins))

    for _ in range(r.randrange(0, 4)):
        kind = r.choice(["point", "spot", "directional", "sphere", "rect"])
        l = ["light", kind]
        if kind not in ("directional", "rect"):
            l += ["position", vec(r, -5, 5)]
        if kind == "sphere":
            l += ["radius", num(r, 0.05, 1.5)]
        if kind == "rect":
            l += ["corner", vec(r, -5, 5), "edge1", vec(r, 0.2, 2), "edge2", vec(r, -2, -0.2)]
        if kind in ("sphere", "rect") and r.random() < 0.7:
            l += ["samples", str(r.choice([1, 2, 3]))]
        if kind == "spot":
            if r.random() < 0.5:
                l += ["target", vec(r, -1.5, 1.5)]
            else:
                l += ["direction", direction(r)]
            l += ["angle", num(r, 5, 120)]
            if r.random() < 0.7:
                l += ["soft", num(r, 0, 20)]
        if kind == "directional":
            l += ["direction", direction(r)]
        if kind != "directional" and r.random() < 0.4:
            l += ["attenuate"]
        if kind in ("sphere", "rect") and "samples" not in l:
            l += ["samples", "2"]  # the default 4 x 4 is slow for a test
        if r.random() < 0.5:
            l += [r.choice(["color", "colour"]), colour(r)]
        if r.random() < 0.6:
            l += ["intensity", num(r, 0.1, 3 if "attenuate" not in l else 30)]
        out.append(" ".join(l))
        if kind in ("point", "sphere") and r.random() < 0.3:  # a lamp: an emissive sphere shows the light
            at = l[l.index("position") + 1]
            rad = float(l[l.index("radius") + 1]) if kind == "sphere" else 0.1
            out.append("material lamp%d emit %s" % (len(out), colour(r, 4)))
            out.append("sphere centre %s radius %.9g material lamp%d" % (at, rad * r.uniform(0.5, 1.5), len(out) - 1))
    env = random.Random(seed * 7919 + 83)  # an environment, a draw of its own (older builds refuse it)
    if newer and env.random() < 0.15:
        out.append("texture envtex %s" % env.choice(["sky.hdr", "sky.hdr", "tq.png"]))
        e = ["environment texture envtex"]
        if env.random() < 0.5:
            e += ["strength", num(env, 0, 3)]
        if env.random() < 0.5:
            e += ["rotate", num(env, -360, 360)]
        out.append(" ".join(e))
    text = "\n".join(out) + "\n"
    # a byte-order mark, as editors on Windows write one
    return ("\ufeff" if r.random() < 0.1 else "") + text


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: randscene.py SEED DIR")
    seed, d = int(sys.argv[1]), sys.argv[2]
    write_assets(d)
    path = os.path.join(d, "scene-%d.scene" % seed)
    with open(path, "w", encoding="utf-8") as f:
        f.write(scene(seed))
    print(path)


if __name__ == "__main__":
    main()
