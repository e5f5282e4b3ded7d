#!/usr/bin/env bash
# The path integrator (settings integrator path): light transport checked
# where the answer is known.  A white furnace: inside a sphere that emits
# radiance 1 everywhere, surfaces that lose no energy (diffuse spheres of
# albedo 1 that light each other, a perfect mirror, clear glass) look like
# the emitter, radiance 1 at every pixel, whatever the bounces between
# them.  The inverse-square law: a floor of albedo 0.5 under an emissive
# sphere of radius 0.5 and radiance 100 at height 5 (and no light) shows
# albedo x radiance x (r / h)^2 = 0.5 below it, where the Whitted
# integrator, whose emission lights nothing, shows black.  A glass ball on
# a floor has no black pixel (each ray of a pixel draws its own numbers).  A path-traced
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
cat >"$dir/furnace.scene" <<'S'
camera position 0 0.5 6 lookat 0 0.3 0 fov 50
background 0 0 0
ambient 0 0 0
settings integrator path depth 64
material sky diffuse 0 0 0 emit 1 1 1
material white diffuse 1 1 1
material mirror reflect 1 1 1
material glass ior 1.5
sphere centre 0 0 0 radius 20 material sky
sphere centre -1 0 0 radius 0.8 material white
sphere centre 0.6 0 0 radius 0.7 material white
sphere centre 0.2 1.2 0 radius 0.5 material mirror
sphere centre 1.4 1.1 0.5 radius 0.45 material glass
plane point 0 -0.9 0 normal 0 1 0 material white
S
"$BIN/lanray-render" "$dir/furnace.scene" --aa 2 --width 48 --height 36 --linear -o "$dir/furnace.ppm" --quiet >/dev/null ||
    fail "the furnace did not render"
read -r mean lo hi <<<"$(ppm_stats "$dir/furnace.ppm")"
[ "$lo" -ge 253 ] || fail "white furnace: a pixel of code $lo where every pixel is the emitter's 255 (mean $mean)"
# the same room of albedo 0.5: it must not look like the emitter (the test can tell)
sed 's/material white diffuse 1 1 1/material white diffuse 0.5 0.5 0.5/' "$dir/furnace.scene" >"$dir/grey.scene"
"$BIN/lanray-render" "$dir/grey.scene" --aa 2 --width 48 --height 36 --linear -o "$dir/grey.ppm" --quiet >/dev/null
read -r gmean glo ghi <<<"$(ppm_stats "$dir/grey.ppm")"
[ "$glo" -lt 200 ] || fail "a grey room in the furnace looks white: the test cannot tell"
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
echo "pathtrace: a glass ball's darkest pixel $blo; a white furnace of diffuse spheres, a mirror and glass comes out 1 (lowest code $lo; a grey room's $glo); the floor under an emissive sphere follows the inverse-square law (code $lmean, 127.5 expected; Whitted $whi); a path-traced frame through 2 clients = lanray-render's"
