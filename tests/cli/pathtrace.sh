#!/usr/bin/env bash
# The path integrator (settings integrator path): light transport checked
# where the answer is known.  A white furnace: inside a sphere that emits
# radiance 1 everywhere, surfaces that lose no energy (diffuse spheres of
# albedo 1 that light each other, coarse balls of smooth triangles, a perfect mirror, clear glass, a half
# mirror over glass that transmits the other half, a veil that scatters
# half diffusely and lets half through, a metal with a Phong highlight of
# its colour, as the importer makes one, a smooth clear coat over white)
# look like
# the emitter, radiance 1 at every pixel, whatever the bounces between
# them (seen at an exposure of -1, so that more than 1 shows).  The inverse-square law: a floor of albedo 0.5 under an emissive
# sphere of radius 0.5 and radiance 100 at height 5 (and no light) shows
# albedo x radiance x (r / h)^2 = 0.5 below it, where the Whitted
# integrator, whose emission lights nothing, shows black.  A glass ball on
# a floor has no black pixel (each ray of a pixel draws its own numbers).
# Emissive geometry lights the same by next-event estimation, by bounces
# and by both under multiple importance sampling.  The Cornell box is
# Blender Cycles' picture within 2%, clear coats within 2.5%, a scanned
# model within 0.8%, a normal-mapped low-poly ball within 1.5%.  A path-traced
# frame through a server and two clients is lanray-render's bit for bit.
set -u
source tests/tools/server-lib.sh
# mean_code FILE.ppm: the mean channel code of a binary PPM, and its min
ppm_stats() {
    python3 - "$1" <<'PY'
import sys
raw = open(sys.argv[1], 'rb').read()
parts = raw.split(maxsplit=4)
data = parts[4]
print("%.3f %d %d" % (sum(data) / len(data), min(data), max(data)))
PY
}
# halves_mean FILE.ppm: the mean channel code of a 48-wide PPM's left and right halves
halves_mean() {
    python3 - "$1" <<'PY'
import sys
raw = open(sys.argv[1], 'rb').read()
data = raw.split(maxsplit=4)[4]
halves = [[], []]
for i, c in enumerate(data):
    halves[(i // 3) % 48 >= 24].append(c)
print(" ".join("%.3f" % (sum(h) / len(h)) for h in halves))
PY
}
cat >"$dir/furnace.scene" <<'S'
camera position 0 0.5 6 lookat 0 0.3 0 fov 50
background 0 0 0
ambient 0 0 0
settings integrator path depth 64
material sky diffuse 0 0 0 emit 1 1 1
material white diffuse 1 1 1
material mirror reflect 1 1 1
material glass ior 1.5
material coated reflect 0.5 0.5 0.5 ior 1.5 transmit 0.5 0.5 0.5
material veil diffuse 0.5 0.5 0.5 ior 1 transmit 0.5 0.5 0.5
material metal reflect 1 1 1 specular 1 1 1 shininess 40
material varnish diffuse 1 1 1 coat 1
sphere centre 0 0 0 radius 20 material sky
sphere centre -1.6 1.3 0.5 radius 0.4 material coated
sphere centre 1.6 -0.4 1.2 radius 0.4 material veil
sphere centre -0.3 -0.5 1.6 radius 0.35 material metal
sphere centre -2.2 -0.3 0.8 radius 0.4 material varnish
sphere centre -1 0 0 radius 0.8 material white
sphere centre 0.6 0 0 radius 0.7 material white
sphere centre 0.2 1.2 0 radius 0.5 material mirror
sphere centre 1.4 1.1 0.5 radius 0.45 material glass
plane point 0 -0.9 0 normal 0 1 0 material white
S
# (a rough metal is not here: its lobe's samples weigh unlike, so its
# pixels are noisy; it has a furnace of its own below)
# and coarse balls of smooth triangles (12 x 6), white and a mirror: their
# bounces leave above the smooth surface, from the point lifted onto it,
# not above each flat facet, and a mirror direction that would go into
# the surface is the facet's (the paths that left below a facet were
# lost: codes 96 at the white ball's triangles' corners and 64 at the
# mirror's rim before 2026-11-29)
printf 'model ball %s/tests/data/mikk/ball.obj\ninstance ball translate 2.2 0.9 -0.5 scale 0.5 material white\n%s\n' \
    "$PWD" "instance ball translate -2.4 1.3 -0.8 scale 0.5 material mirror" >>"$dir/furnace.scene"
# found by the paths alone, every path brings exactly the emitter's 1
"$BIN/lanray-render" "$dir/furnace.scene" --emitter-sampling bsdf --aa 2 --width 48 --height 36 --linear \
    --exposure -1 -o "$dir/furnace.ppm" --quiet >/dev/null || fail "the furnace did not render"
read -r mean lo hi <<<"$(ppm_stats "$dir/furnace.ppm")"
[ "$lo" -ge 126 ] && [ "$hi" -le 129 ] ||
    fail "white furnace: codes $lo to $hi where every pixel is the emitter's 127.5 at exposure -1 (mean $mean)"
# the same room of albedo 0.5: it must not look like the emitter (the
# test can tell; the metal with its highlight as a whole glossy lobe
# beside its mirror, as before 2026-11-29, failed it: codes 96 to 255)
sed 's/material white diffuse 1 1 1/material white diffuse 0.5 0.5 0.5/' "$dir/furnace.scene" >"$dir/grey.scene"
"$BIN/lanray-render" "$dir/grey.scene" --emitter-sampling bsdf --aa 2 --width 48 --height 36 --linear \
    --exposure -1 -o "$dir/grey.ppm" --quiet >/dev/null
read -r gmean glo ghi <<<"$(ppm_stats "$dir/grey.ppm")"
[ "$glo" -lt 100 ] || fail "a grey room in the furnace looks white: the test cannot tell"
# a rough clear coat over white: its glossy lobe loses what falls below
# the surface, nothing more, and adds nothing (its Fresnel share and the
# white under it make 1 at most)
sed 's/^material varnish diffuse 1 1 1 coat 1$/material varnish diffuse 1 1 1 coat 1 coat_roughness 0.5/' \
    "$dir/furnace.scene" >"$dir/satin.scene"
"$BIN/lanray-render" "$dir/satin.scene" --emitter-sampling bsdf --aa 4 --width 48 --height 36 --linear \
    --exposure -1 -o "$dir/satin.ppm" --quiet >/dev/null || fail "the satin furnace did not render"
read -r cmean clo chi <<<"$(ppm_stats "$dir/satin.ppm")"
python3 -c "import sys; sys.exit(0 if $clo >= 80 and $chi <= 129 and $cmean >= 125 else 1)" ||
    fail "a rough coat in the furnace: codes $clo to $chi (mean $cmean), 80 to 128 expected (mean 125 or more) at exposure -1"
# rough white metals (GGX roughness 0.5 and 1) filling the frame in the
# furnace: each lobe weighed by ggx_metal for the light that meets a
# second facet (Turquin's and Kulla and Conty's compensation, tools/ggx-tables), each
# ball's mean the emitter's 127.5 within 1%.  The single-scattering lobe
# alone (before 2026-11-29, as Cycles 3.4's plain GGX) lost it: 118 and 92.
cat >"$dir/metals.scene" <<'S'
camera position 0 0 4 lookat 0 0 0 fov 50
background 0 0 0
ambient 0 0 0
settings integrator path depth 64
material sky diffuse 0 0 0 emit 1 1 1
material satin reflect 1 1 1 roughness 0.5
material rough reflect 1 1 1 roughness 1
sphere centre 0 0 0 radius 20 material sky
sphere centre -0.9 0 0 radius 0.85 material satin
sphere centre 0.9 0 0 radius 0.85 material rough
S
"$BIN/lanray-render" "$dir/metals.scene" --aa 8 --width 48 --height 36 --linear --exposure -1 -o "$dir/metals.ppm" \
    --quiet >/dev/null || fail "the rough metals' furnace did not render"
read -r ml mr <<<"$(halves_mean "$dir/metals.ppm")"
python3 -c "import sys; sys.exit(0 if abs($ml - 127.5) <= 1.3 and abs($mr - 127.5) <= 1.3 else 1)" ||
    fail "rough white metals in the furnace: means $ml and $mr, 127.5 expected (within 1%)"
# and clear frosted glass, index 1.5 of roughness 0.5 and index 2 of
# roughness 1: each lobe weighed by ggx_glass_weight (its light kept at a
# surface, by index and side: tools/ggx-tables), the balls vanish into
# the furnace, means within 1%; the lobe alone: 114 and 81
sed 's/^material satin .*/material satin ior 1.5 roughness 0.5/; s/^material rough .*/material rough ior 2 roughness 1/' \
    "$dir/metals.scene" >"$dir/frosted-furnace.scene"
"$BIN/lanray-render" "$dir/frosted-furnace.scene" --aa 8 --width 48 --height 36 --linear --exposure -1 \
    -o "$dir/frosted-furnace.ppm" --quiet >/dev/null || fail "the frosted glass furnace did not render"
read -r gl gr <<<"$(halves_mean "$dir/frosted-furnace.ppm")"
python3 -c "import sys; sys.exit(0 if abs($gl - 127.5) <= 1.3 and abs($gr - 127.5) <= 1.3 else 1)" ||
    fail "frosted glass in the furnace: means $gl and $gr, 127.5 expected (within 1%)"
# clear coats against Cycles: a smooth and a rough coat (Cycles: a sharp
# and a GGX glossy mixed over the diffuse by a Fresnel node, written by
# tools/bench/scene2cycles) under a sky and a lamp; the stored reference
# is Cycles' 64x48 frame at 4096 samples (tests/data/cycles/coat.scene):
# lanray's at 256 within 2.5% in 4x4 blocks and its light within 1.5%.
# The same spheres without their coats are 6% off: the test can tell.
# (Not under the sanitizers: the furnace above runs the coats' code.)
co_err="(not measured under a sanitizer)" un_err=-
if [ "$sanitized" = 0 ]; then
    "$BIN/lanray-render" tests/data/cycles/coat.scene --aa 16 -o "$dir/coat.hdr" --quiet >/dev/null ||
        fail "coat.scene did not render"
    IFS=, read -r co_err co_ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/coat.hdr" tests/data/cycles/coat-64.hdr)"
    python3 -c "import sys; sys.exit(0 if $co_err <= 0.025 and abs($co_ratio - 1) <= 0.015 else 1)" ||
        fail "clear coats: $co_err (mean relative error, 4x4 blocks; light ratio $co_ratio) from Cycles'"
    sed 's/ coat 1 coat_roughness 0.3$//; s/ coat 1$//' tests/data/cycles/coat.scene >"$dir/uncoated.scene"
    "$BIN/lanray-render" "$dir/uncoated.scene" --aa 16 -o "$dir/uncoated.hdr" --quiet >/dev/null
    IFS=, read -r un_err un_ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/uncoated.hdr" tests/data/cycles/coat-64.hdr)"
    python3 -c "import sys; sys.exit(0 if $un_err > 0.04 else 1)" || fail "uncoated spheres pass for coated ones ($un_err): the test cannot tell"
fi
# a scanned model against Cycles (tests/data/cycles/dragon.scene: the
# 20k-triangle models/dragon.obj, smooth normals, on a floor under an
# emissive quad and a sky; Cycles' 96x72 frame at 4096 samples stored):
# lanray's at 64 samples within 0.8% in 4x4 blocks and its light within
# 1%.  Before 2026-11-29 every light ray of a smooth triangle left from
# the point lifted onto its curved surface, inside the next fold of this
# mesh's ridges: 1.9% off, its light 2% short (14% of its direct light).
# against_cycles NAME AA MAX_ERR WHAT [MAX_RATIO]: tests/data/cycles/NAME.scene
# at AA x AA samples within MAX_ERR (mean relative error in 4x4 blocks) of
# Cycles' stored NAME-96.hdr, its light within MAX_RATIO (1%); the error in $err
against_cycles() {
    err="(not measured under a sanitizer)"
    [ "$sanitized" = 0 ] || return 0
    "$BIN/lanray-render" "tests/data/cycles/$1.scene" --aa "$2" -o "$dir/$1.hdr" --quiet >/dev/null ||
        fail "$1.scene did not render"
    local ratio
    IFS=, read -r err ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/$1.hdr" "tests/data/cycles/$1-96.hdr")"
    python3 -c "import sys; sys.exit(0 if $err <= $3 and abs($ratio - 1) <= ${5:-0.01} else 1)" ||
        fail "$4: $err (mean relative error, 4x4 blocks; light ratio $ratio) from Cycles'"
}
against_cycles dragon 8 0.008 "a scanned dragon"
dr_err=$err
# a normal map against Cycles' (tests/data/cycles/mapped.scene: the
# 12 x 6 ball whose map was baked in Blender's tangent frames, under the
# same lamp and sky; Cycles reads it through a tangent-space Normal Map
# node): within 1.5% in 4x4 blocks, its light within 1%.  Before
# 2026-11-29 (each triangle's own frame, the facets deciding what a light
# or a bounce may do, no shadowing term for the map): 3.9% off.
against_cycles mapped 8 0.015 "a normal-mapped ball"
nm_err=$err
# rough metals against Cycles' Glossy BSDF (tests/data/cycles/metals.scene:
# roughness 0.15, 0.35, 0.7 and a gold one of 0.5 under the same lamp and
# sky; Cycles' frame at 4096 samples, Multiscatter GGX): within 1% in 4x4
# blocks, its light within 1%.  Before 2026-11-29 a rough metal's ray was
# the mirror direction bent by a point of a ball of radius `roughness`:
# 6.8% off, its light 6% over (a very rough ball a blurred mirror, not a
# satin sheen); the single-scattering GGX lobe alone: 5.9% off, light
# 0.933.
against_cycles metals 16 0.01 "rough metals"
mt_err=$err
# metals whose colour rises to white at grazing angles (reflect_edge,
# glTF's metals) against Cycles' Principled BSDF, metallic 1
# (tests/data/cycles/edged.scene: a smooth and a rough gold, a rough copper
# and a dark steel; Cycles' frame at 4096 samples, Multiscatter GGX):
# within 1.3% in 4x4 blocks, its light within 1% (0.94%, 0.997; the same
# metals without the rise 1.97%, 0.991).  Cycles' rise follows a
# dielectric's Fresnel, Schlick's (glTF's) a little less at middle angles:
# the dark steel's box 2.7% darker; sharp metals against Cycles' Glossy
# tinted by Schlick's weight (a Layer Weight node) within 0.31%, light 1.000.
against_cycles edged 16 0.013 "edged metals"
eg_err=$err
# frosted glass against Cycles' rough Glass BSDF, Multiscatter GGX
# (tests/data/cycles/frosted.scene: balls of roughness 0.1, 0.3 and 0.6
# and a clear one before a red wall; Cycles' frame at 4096 samples, its
# glass balls fine meshes, its lamp and sky found by the paths alone, as
# scene2cycles has it beside frosted glass): within 3% in 4x4 blocks, its
# light within 1% (2.4%, 0.995; ball by ball within 1.2% at 1024
# samples).  The single-scattering lobe alone (before 2026-11-29, later):
# 5.2%, light 0.948; the balls clear 4.7% off.
against_cycles frosted 16 0.03 "frosted glass"
fg_err=$err
# light from everywhere against Cycles' Environment Texture
# (tests/data/cycles/environment.scene: a sky panorama with a sun, turned
# 40 degrees, over a white, a rough gold and a chrome ball on a floor;
# Cycles' frame at 4096 samples): within 2% in 4x4 blocks at 256 samples,
# its light within 1% (1.12%, 1.0014; 0.61% at 1024 samples; 2.1% and 1.1%
# before the draws followed the bilinear light, 2026-11-30, 1.32% and
# 0.85% before they went to what stands out, 1.23%, 1.005 before
# scene2cycles handed Cycles the panorama as lanray reads it).  Before
# 2026-11-29 lanray had no environment.
against_cycles environment 16 0.02 "an environment"
ev_err=$err
# caustics against Cycles' (tests/data/cycles/caustics.scene: the same
# sky over a glass, a rough gold and a chrome ball; Cycles' frame at 4096
# samples): the sun the balls bring to the floor, found by bounces alone,
# within 2.5% in 4x4 blocks at 256 samples, its light within 1% (1.74%,
# 1.0026; 0.98% at 1024; 1.87%, 1.0056 with Blender's own reading of
# the panorama).  tests/cli/filterglossy.sh blurs them.
against_cycles caustics 16 0.025 "caustics"
ca_err=$err
# a glTF scene as Blender exports one (tests/data/gltf/lit.glb, made by
# tools/bench/make-lit-glb: a ball and a box on a floor under a point lamp
# and a sun, its camera): lanray-render's preview of the file takes its
# camera and its lights (KHR_lights_punctual, candela and lux), within 1%
# in 4x4 blocks of Cycles' frame of the same file through Blender's own
# importer (its diffuse materials Lambert's, glTF's BRDF: scene2cycles
# --lambert 1; 4096 samples), light within 1% (0.28%, 1.002 at 64
# samples).  Before 2026-11-29 the preview framed the model itself under
# two lamps of its own.
gl_err="(not measured under a sanitizer)"
if [ "$sanitized" = 0 ]; then
    "$BIN/lanray-render" tests/data/gltf/lit.glb --integrator path --aa 8 --width 96 --height 72 -o "$dir/lit.hdr" \
        --quiet >/dev/null || fail "lit.glb did not render"
    IFS=, read -r gl_err gl_ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/lit.hdr" tests/data/cycles/lit-96.hdr)"
    python3 -c "import sys; sys.exit(0 if $gl_err <= 0.01 and abs($gl_ratio - 1) <= 0.01 else 1)" ||
        fail "a Blender-exported glTF's camera and lights: $gl_err from Cycles' (light ratio $gl_ratio)"
fi
# a smooth coat over a rough metal reflects sharply: its mirror is not
# bent by the metal's roughness (a metal of 0.1% under it: the picture is
# the coat's alone within RMSE 5; bent with it, as before, RMSE 14.4)
# a see-through blend (a dielectric of index 1: glTF's BLEND, an MTL's
# dissolve) over the left half of a floor under a point light, seen from
# above through it: the path integrator's shadow rays pass it times its
# transmit (0.5), as the Whitted integrator's do, so the left half is a
# quarter of the right (half the light, seen through half); before
# 2026-11-29 they stopped there, and since no path meets a point light
# the floor under it was black
cat >"$dir/veil.scene" <<'S'
camera position 0 3 0.001 lookat 0 0 0 fov 60
background 0 0 0
ambient 0 0 0
settings integrator path depth 4 width 48 height 36 aa 4
material floor diffuse 0.8 0.8 0.8
material veil ior 1 transmit 0.5 0.5 0.5
plane point 0 0 0 normal 0 1 0 material floor
triangle vertices -3 1 -3  0 1 -3  0 1 3 material veil
triangle vertices -3 1 -3  0 1 3  -3 1 3 material veil
light point position 0 2.5 0 intensity 0.5
S
"$BIN/lanray-render" "$dir/veil.scene" --linear -o "$dir/veil.ppm" --quiet >/dev/null || fail "veil.scene did not render"
"$BIN/lanray-render" "$dir/veil.scene" --integrator whitted --linear -o "$dir/veil-w.ppm" --quiet >/dev/null ||
    fail "veil.scene (Whitted) did not render"
read -r vl vr <<<"$(halves_mean "$dir/veil.ppm")"
read -r wl wr <<<"$(halves_mean "$dir/veil-w.ppm")"
python3 -c "import sys; sys.exit(0 if abs($vl / $vr - 0.25) < 0.01 and abs($vl / $wl - 1) < 0.03 else 1)" ||
    fail "a point light through a see-through blend: path $vl | $vr, Whitted $wl | $wr (the left half a quarter of the right, as Whitted's)"
cat >"$dir/sharp.scene" <<'S'
camera position 0 0 4 lookat 0 0 0 fov 30
background 0 0 0
settings integrator path depth 2 aa 4 width 64 height 64
material coat diffuse 0 0 0 coat 1
material lamp diffuse 0 0 0 emit 50 50 50
sphere centre 0 0 0 radius 1 material coat
sphere centre 1.5 1.5 3 radius 0.2 material lamp
S
sed 's/^material coat diffuse 0 0 0 coat 1$/material coat diffuse 0 0 0 reflect 0.001 0.001 0.001 roughness 1 coat 1/' \
    "$dir/sharp.scene" >"$dir/over.scene"
for s in sharp over; do
    "$BIN/lanray-render" "$dir/$s.scene" -o "$dir/$s.png" --quiet >/dev/null || fail "$s.scene did not render"
done
sh_rmse=$("$BIN/lanray-imgdiff" --csv "$dir/sharp.png" "$dir/over.png" | cut -d, -f3)
python3 -c "import sys; sys.exit(0 if $sh_rmse < 5 else 1)" ||
    fail "a smooth coat over a rough metal is not the coat's sharp reflection: RMSE $sh_rmse"
# a rough coat's highlight is the same light under both integrators: the
# Whitted integrator's normalised as the path integrator's lobe, so at
# depth 0 (direct light only) the two pictures agree
cat >"$dir/agree.scene" <<'S'
camera position 0 0.3 4 lookat 0 0 0 fov 35
background 0 0 0
ambient 0 0 0
settings width 96 height 64 aa 1 depth 0
material satin diffuse 0.6 0.3 0.1 coat 0.8 coat_roughness 0.4
sphere centre 0 0 0 radius 1 material satin
light point position 3 4 4 intensity 0.9
light directional direction 1 -1 -1 intensity 0.3
S
# direct_agree NAME WHAT: $dir/NAME.scene's picture under both integrators
# the same light (within 1e-4); the error in $da_err
direct_agree() {
    local ratio
    "$BIN/lanray-render" "$dir/$1.scene" -o "$dir/$1-w.hdr" --quiet >/dev/null &&
        "$BIN/lanray-render" "$dir/$1.scene" --integrator path -o "$dir/$1-p.hdr" --quiet >/dev/null ||
        fail "$1.scene did not render"
    IFS=, read -r da_err ratio <<<"$("$BIN/lanray-imgdiff" --relative --csv "$dir/$1-p.hdr" "$dir/$1-w.hdr")"
    python3 -c "import sys; sys.exit(0 if $da_err <= 1e-4 and abs($ratio - 1) <= 1e-4 else 1)" ||
        fail "$2: path $da_err from Whitted's (light ratio $ratio)"
}
direct_agree agree "a rough coat's direct light"
ag_err=$da_err
# so is a rough metal's without a `specular` of its own (a plain gold and
# a steel with a rim): since 2026-11-29 the Whitted integrator's highlight
# of such a metal is its GGX lobe, as its rays' and the path integrator's,
# where it had none (a Phong `specular`, an imported metal's, stays)
sed -e 's/^material satin .*/material satin reflect 1 0.78 0.34 roughness 0.4/' \
    -e 's/^sphere centre 0 0 0 radius 1 material satin/sphere centre -0.55 0 0 radius 0.5 material satin\nmaterial steel reflect 0.2 0.2 0.22 roughness 0.25 reflect_edge 1 1 1\nsphere centre 0.55 0 0 radius 0.5 material steel/' \
    "$dir/agree.scene" >"$dir/metal.scene"
direct_agree metal "a rough metal's direct light"
mg_err=$da_err
# frosted glass is the same under both integrators where what it shows
# is emission alone (stripes behind a frosted ball, no light, no cutoff):
# the Whitted integrator's rough_samples^2 facets a pixel against the
# path integrator's paths, within 1.5% in 4x4 blocks; the ball clear
# under Whitted is 4% off
cat >"$dir/frost-w.scene" <<'S'
camera position 0 0.5 3 lookat 0 0.5 0 fov 40
background 0 0 0
ambient 0 0 0
settings depth 8 cutoff 0 width 64 height 48
material frost ior 1.5 roughness 0.3
material red diffuse 0 0 0 emit 1 0.2 0.1
material blue diffuse 0 0 0 emit 0.1 0.3 1
sphere centre 0 0.5 0 radius 0.6 material frost
triangle vertices -3 -1 -2  -1 -1 -2  -1 3 -2 material red
triangle vertices -3 -1 -2  -1 3 -2  -3 3 -2 material red
triangle vertices -1 -1 -2  1 -1 -2  1 3 -2 material blue
triangle vertices -1 -1 -2  1 3 -2  -1 3 -2 material blue
triangle vertices 1 -1 -2  3 -1 -2  3 3 -2 material red
triangle vertices 1 -1 -2  3 3 -2  1 3 -2 material red
S
sed 's/ roughness 0.3$//' "$dir/frost-w.scene" >"$dir/clear-w.scene"
"$BIN/lanray-render" "$dir/frost-w.scene" --aa 4 -o "$dir/frost-w.hdr" --quiet >/dev/null 2>&1 &&
    "$BIN/lanray-render" "$dir/clear-w.scene" --aa 4 -o "$dir/clear-w.hdr" --quiet >/dev/null 2>&1 &&
    "$BIN/lanray-render" "$dir/frost-w.scene" --integrator path --aa 16 -o "$dir/frost-p.hdr" --quiet >/dev/null 2>&1 ||
    fail "frost-w.scene did not render"
IFS=, read -r fw_err fw_ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/frost-w.hdr" "$dir/frost-p.hdr")"
python3 -c "import sys; sys.exit(0 if $fw_err <= 0.015 and abs($fw_ratio - 1) <= 0.01 else 1)" ||
    fail "frosted glass: the Whitted integrator's $fw_err from the path integrator's (light ratio $fw_ratio)"
IFS=, read -r cw_err _ <<<"$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/clear-w.hdr" "$dir/frost-p.hdr")"
python3 -c "import sys; sys.exit(0 if $cw_err > 0.025 else 1)" || fail "clear glass passes for frosted ($cw_err): the test cannot tell"
# that highlight still shows the lights no ray can meet (a point light)
cat >"$dir/shine.scene" <<'S'
camera position 0 0 4 lookat 0 0 0 fov 30
background 0.1 0.1 0.1
settings integrator path depth 4
material metal reflect 0.5 0.5 0.5 specular 0.5 0.5 0.5 shininess 100
sphere centre 0 0 0 radius 0.8 material metal
light point position 2 2 5 intensity 1
S
sed 's/ specular 0.5 0.5 0.5 shininess 100//' "$dir/shine.scene" >"$dir/dull.scene"
# and frosted glass shows a point light, which no path can meet: its
# facets take it by next-event estimation from either side (clear glass, a
# mirror to it, does not)
sed 's/^material metal .*/material metal ior 1.5 roughness 0.3/' "$dir/shine.scene" >"$dir/frost.scene"
sed 's/^material metal .*/material metal ior 1.5/' "$dir/shine.scene" >"$dir/clear.scene"
for s in shine dull frost clear; do
    "$BIN/lanray-render" "$dir/$s.scene" --aa 2 --width 48 --height 48 --linear -o "$dir/$s.ppm" --quiet >/dev/null ||
        fail "$s.scene did not render"
done
read -r smean slo shi <<<"$(ppm_stats "$dir/shine.ppm")"
read -r dmean dlo dhi <<<"$(ppm_stats "$dir/dull.ppm")"
[ "$shi" -ge 250 ] && [ "$dhi" -lt 100 ] ||
    fail "a metal's highlight of a point light: brightest code $shi with it, $dhi without"
read -r fmean flo fhi <<<"$(ppm_stats "$dir/frost.ppm")"
read -r cmean2 clo2 chi2 <<<"$(ppm_stats "$dir/clear.ppm")"
[ "$fhi" -ge 250 ] && [ "$chi2" -lt 100 ] ||
    fail "frosted glass under a point light: brightest code $fhi (clear glass $chi2)"
cat >"$dir/lamp.scene" <<'S'
camera position 0 4 0 yaw 0 pitch -90 ortho 0.2
background 0 0 0
ambient 0 0 0
settings integrator path depth 4
material floor diffuse 0.5 0.5 0.5
material bulb diffuse 0 0 0 emit 100 100 100
plane point 0 0 0 normal 0 1 0 material floor
sphere centre 0 5 0 radius 0.5 material bulb
S
# (the camera looks straight down from below the bulb at the floor's middle, 0.2 wide)
"$BIN/lanray-render" "$dir/lamp.scene" --aa 16 --width 32 --height 32 --linear -o "$dir/lamp.ppm" --quiet >/dev/null ||
    fail "the lamp scene did not render"
read -r lmean llo lhi <<<"$(ppm_stats "$dir/lamp.ppm")"
python3 -c "import sys; m = $lmean; sys.exit(0 if abs(m - 127.5) < 0.04 * 127.5 else 1)" ||
    fail "inverse-square law: the floor under the bulb shows code $lmean, 0.5 x 100 x (0.5/5)^2 = 0.5 is 127.5"
sed 's/integrator path/integrator whitted/' "$dir/lamp.scene" >"$dir/lamp-w.scene"
"$BIN/lanray-render" "$dir/lamp-w.scene" --aa 1 --width 32 --height 32 --linear -o "$dir/lamp-w.ppm" --quiet >/dev/null
read -r wmean wlo whi <<<"$(ppm_stats "$dir/lamp-w.ppm")"
[ "$whi" = 0 ] || fail "the Whitted integrator lit the floor by emission (code $whi): the test cannot tell"
# a glass ball on a floor under the sky: its rays choose reflection or
# refraction, and Russian roulette ends some of them, each by its own
# number; when every ray of a pixel drew the same numbers, whole pixels of
# the ball came out black
cat >"$dir/ball.scene" <<'S'
camera position 13 2 3 lookat 0 0.8 0 fov 15
background 0.75 0.85 1
settings integrator path depth 49 fresnel schlick
material glass ior 1.5
material ground diffuse 0.5 0.5 0.5
sphere centre 0 1 0 radius 1 material glass
plane point 0 0 0 normal 0 1 0 material ground
S
"$BIN/lanray-render" "$dir/ball.scene" --aa 4 --width 64 --height 48 --linear -o "$dir/ball.ppm" --quiet >/dev/null ||
    fail "the glass ball did not render"
read -r bmean blo bhi <<<"$(ppm_stats "$dir/ball.ppm")"
[ "$blo" -ge 20 ] || fail "a glass ball on a floor has a black pixel (code $blo): the rays of a pixel chose alike"
# emissive geometry (a ceiling panel of two triangles, a small bright
# sphere; no light) lighting a floor, a rough metal, a sphere with a
# glossy Phong lobe and a frosted glass ball (its facets lit from both
# sides), found three ways: by next-event estimation alone, by
# the bounces that meet it alone, and by both weighed by multiple
# importance sampling: one picture, in the light of 6x6-pixel blocks
# (their noise averaged; a bias stays).  A panel 4% brighter is told apart.
cat >"$dir/mis.scene" <<'S'
camera position 0 1.9 4 lookat 0 0.4 0 fov 45
background 0 0 0
ambient 0 0 0
settings integrator path depth 4
material floor diffuse 0.6 0.6 0.6
material red diffuse 0.5 0.15 0.1 specular 0.4 0.4 0.4 shininess 40
material metal reflect 0.8 0.8 0.8 roughness 0.3
material frost ior 1.5 roughness 0.4
material panel diffuse 0 0 0 emit 1.5 1.5 1.3
material bulb diffuse 0 0 0 emit 40 32 24
plane point 0 0 0 normal 0 1 0 material floor
sphere centre -0.6 0.5 0 radius 0.5 material red
sphere centre 0.7 0.4 0.3 radius 0.4 material metal
sphere centre -0.2 0.25 1.0 radius 0.25 material frost
sphere centre 2.5 1.2 -0.5 radius 0.12 material bulb
triangle vertices -2 2.5 -2.5 2 2.5 -2.5 2 2.5 0.5 material panel
triangle vertices -2 2.5 -2.5 2 2.5 0.5 -2 2.5 0.5 material panel
S
for m in mis nee bsdf; do
    "$BIN/lanray-render" "$dir/mis.scene" --emitter-sampling $m --aa 16 --width 48 --height 36 -o "$dir/mis-$m.hdr" \
        --quiet >/dev/null || fail "the emitters' scene did not render with emitter_sampling $m"
done
# within_light A.hdr REF.hdr MAX_ERROR: block error and mean ratio, or fail
within_light() {
    local out err ratio
    out=$("$BIN/lanray-imgdiff" --relative --block 6 --csv "$1" "$2") || fail "imgdiff failed on $1"
    IFS=, read -r err ratio <<<"$out"
    python3 -c "import sys; sys.exit(0 if $err <= $3 and abs($ratio - 1) <= 0.015 else 1)" || return 1
    echo "$err $ratio"
}
# (each result taken apart from its read: a read of a failed command's
# output succeeds, and these checks never failed before 2026-11-30; NEE
# alone at 16x16 is 0.021 off its own 32x32 picture here, hence 0.03)
out=$(within_light "$dir/mis-nee.hdr" "$dir/mis-mis.hdr" 0.03) ||
    fail "emitters by next-event estimation alone differ from MIS beyond the noise"
read -r nee_err nee_ratio <<<"$out"
out=$(within_light "$dir/mis-bsdf.hdr" "$dir/mis-mis.hdr" 0.08) ||
    fail "emitters by bounces alone differ from MIS beyond the noise"
read -r bsdf_err bsdf_ratio <<<"$out"
sed 's/emit 1.5 1.5 1.3/emit 1.56 1.56 1.352/' "$dir/mis.scene" >"$dir/mis4.scene"
"$BIN/lanray-render" "$dir/mis4.scene" --emitter-sampling nee --aa 16 --width 48 --height 36 -o "$dir/mis4.hdr" --quiet >/dev/null
within_light "$dir/mis4.hdr" "$dir/mis-mis.hdr" 0.03 >/dev/null && fail "a panel 4% brighter passes: the test cannot tell"
# the furnace under MIS (the default): the emitter sampled as well, so
# each path brings 1 only on average: within the noise of 6x6 blocks
for m in mis bsdf; do
    "$BIN/lanray-render" "$dir/furnace.scene" --emitter-sampling $m --aa 8 --width 48 --height 36 -o "$dir/f-$m.hdr" \
        --quiet >/dev/null || fail "the furnace did not render with emitter_sampling $m"
done
out=$(within_light "$dir/f-mis.hdr" "$dir/f-bsdf.hdr" 0.02) ||
    fail "white furnace under MIS: not the emitter's radiance within the noise"
read -r fur_err fur_ratio <<<"$out"
# the Cornell box (models/cornell.scene) against Blender's Cycles: the
# stored reference is Cycles' 64x64 frame at 4096 samples a pixel, made by
# tools/bench/scene2cycles (docs/renderer.md); lanray's at 256 within 2%
# mean relative error in 4x4-pixel blocks (the noise of 256 samples
# averaged; a bias stays), and its light within 1%.  The box lit only one
# bounce deep misses its bounced light: the test can tell.  (Not under
# the sanitizers: 15 s there of the code the scenes above run.)
cb_err="(not measured under a sanitizer)" cb_ratio=-
if [ "$sanitized" = 0 ]; then
    "$BIN/lanray-render" models/cornell.scene --integrator path --depth 32 --aa 16 --width 64 --height 64 \
        -o "$dir/cornell.hdr" --quiet >/dev/null || fail "the Cornell box did not render"
    out=$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/cornell.hdr" tests/data/cycles/cornell-64.hdr) ||
        fail "imgdiff failed on the Cornell box"
    IFS=, read -r cb_err cb_ratio <<<"$out"
    python3 -c "import sys; sys.exit(0 if $cb_err <= 0.02 and abs($cb_ratio - 1) <= 0.01 else 1)" ||
        fail "the Cornell box is $cb_err (mean relative error, 4x4 blocks; light ratio $cb_ratio) from Cycles'"
    "$BIN/lanray-render" models/cornell.scene --integrator path --depth 1 --aa 16 --width 64 --height 64 \
        -o "$dir/cornell1.hdr" --quiet >/dev/null
    out=$("$BIN/lanray-imgdiff" --relative --block 4 --csv "$dir/cornell1.hdr" tests/data/cycles/cornell-64.hdr)
    python3 -c "import sys; sys.exit(0 if ${out%,*} > 0.05 else 1)" || fail "one bounce of the Cornell box passes: the test cannot tell"
fi
# a path-traced frame through a server and two clients
cat >"$dir/room.scene" <<'S'
camera position 0 1 5 lookat 0 0.5 0 fov 50
background 0.2 0.25 0.3
settings integrator path depth 6
material red diffuse 0.7 0.1 0.1
material metal reflect 0.8 0.8 0.7 roughness 0.2
material glass ior 1.5 transmit 0.9 1 0.9
material bulb diffuse 0 0 0 emit 8 7 6
plane point 0 0 0 normal 0 1 0
sphere centre -1 0.5 0 radius 0.5 material red
sphere centre 0.2 0.5 -0.5 radius 0.5 material metal
sphere centre 1.2 0.4 0.6 radius 0.4 material glass
sphere centre 0 2.5 1 radius 0.3 material bulb
light point position 2 3 2 color 1 1 1 intensity 0.6
S
"$BIN/lanray-render" "$dir/room.scene" --aa 2 --width 64 --height 64 -o "$dir/room.png" --quiet >/dev/null ||
    fail "the room did not render"
start_server room "$dir/room.scene" --port 0 --width 64 --height 64 --aa 2 --frames 1 --wait-clients 2 --verify "$dir/room.png" \
    --out "$dir/f-room"
clients_until_done 2 1
wait "$server_pid" || fail "the path-traced frame through 2 clients differs from lanray-render's (server exit $?)"
echo "pathtrace: the Cornell box $cb_err from Cycles' (4x4 blocks, light ratio $cb_ratio); a scanned dragon $dr_err; a normal-mapped ball $nm_err; rough metals $mt_err; edged metals $eg_err; frosted glass $fg_err; an environment $ev_err; caustics $ca_err; a Blender-exported glTF's camera and lights $gl_err; white furnace under MIS within $fur_err (6x6 blocks, light ratio $fur_ratio); emitters by NEE alone and by bounces alone = MIS (6x6 blocks: error $nee_err and $bsdf_err, light ratio $nee_ratio and $bsdf_ratio); a glass ball's darkest pixel $blo; a white furnace of diffuse spheres, coarse balls of smooth triangles (white and a mirror), a mirror, glass, a mirror over glass, a see-through diffuse veil and a metal with a highlight and a smooth clear coat come out 1 (codes $lo to $hi at exposure -1; rough white metals $ml and $mr (127.5; single scattering alone 118 and 92), frosted glass $gl and $gr, a rough coat $clo to $chi, its direct light Whitted's within $ag_err (rough metals' $mg_err), coats $co_err from Cycles' (uncoated $un_err), a smooth coat over a rough metal sharp (RMSE $sh_rmse); the highlight shows a point light: $shi, without it $dhi, frosted glass $fhi, clear $chi2; frosted glass under Whitted the path integrator's within $fw_err (clear $cw_err); a grey room's $glo); a point light through a see-through blend $vl of $vr (Whitted $wl of $wr); the floor under an emissive sphere follows the inverse-square law (code $lmean, 127.5 expected; Whitted $whi); a path-traced frame through 2 clients = lanray-render's"
