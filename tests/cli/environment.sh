#!/usr/bin/env bash
# Light from everywhere (`environment texture T`, scene/environment.h): a
# panorama that rays leaving the scene see and that lights it.
# - A white furnace: a ball of diffuse 1 inside a constant panorama of 0.5
#   shows 0.5 everywhere (linear code 128 with --linear), path-traced (next-event estimation, bounces and MIS) and
#   under the Whitted integrator (its irradiance from nine spherical
#   harmonics); without the environment it was the background's black.
# - The Whitted integrator takes the sky's sun as a directional light with
#   shadows: within 10% of the path-traced picture in 6x6 blocks, and less
#   than half the error without its shadows.
# - A sky with a sun: next-event estimation of the panorama alone, bounces
#   alone and MIS give the same light (6x6 blocks within 5%, means within 1%).
# - `rotate` turns the panorama as a camera's yaw turns.
# - Bad input: an unknown texture, a second environment, a cut .hdr are
#   errors naming the file and line.
# - --environment FILE on the command line (lanray-render, lanray-server)
#   puts one around any scene, --environment-strength and -rotate change it.
# - Every SIMD path gives the same bytes; a server with a client
#   lanray-render's, Whitted and path-traced (the .hdr travels as a texture
#   asset of its own bytes).
set -u
source tests/tools/server-lib.sh
python3 tests/tools/envmap.py "$dir/grey.hdr" constant 32 16 0.5 0.5 0.5
python3 tests/tools/envmap.py "$dir/sky.hdr" sky 64 32 0.3 0.22 0.12 80
cat >"$dir/furnace.scene" <<'S'
camera position 0 0 3 lookat 0 0 0 ortho 3
ambient 0 0 0
texture grey grey.hdr
environment texture grey
material white diffuse 1 1 1
sphere centre 0 0 0 radius 1 material white
S
# the ball's centre and a point near its rim (the background at the corner)
px() { python3 tests/tools/pngpixel.py "$1" 16 16 27 16 1 1 | tr '\n' ' '; }
for integ in whitted path; do
    "$BIN/lanray-render" "$dir/furnace.scene" --integrator $integ --width 32 --height 32 --aa 8 --linear \
        -o "$dir/furnace-$integ.png" --quiet >"$dir/f.log" 2>&1 || fail "furnace ($integ): $(cat "$dir/f.log")"
    got=$(px "$dir/furnace-$integ.png")
    for v in $got; do
        [ "$v" -ge 126 ] && [ "$v" -le 130 ] || fail "a white ball in a grey furnace ($integ) should show 0.5 (code 128): $got"
    done
done
furnace=$got
cat >"$dir/sky.scene" <<'S'
camera position 0 1 3 lookat 0 0.4 0
settings width 48 height 36 integrator path depth 4
texture sky sky.hdr
environment texture sky strength 1 rotate 20
material white diffuse 0.8 0.8 0.8
material gold reflect 1 0.78 0.34 roughness 0.35
sphere centre -0.6 0.5 0 radius 0.5 material white
sphere centre 0.6 0.5 0 radius 0.5 material gold
plane point 0 0 0 normal 0 1 0
S
for m in mis nee bsdf; do
    "$BIN/lanray-render" "$dir/sky.scene" --aa 16 --emitter-sampling $m -o "$dir/sky-$m.hdr" --quiet >/dev/null 2>&1 ||
        fail "sky ($m)"
done
for m in nee bsdf; do
    IFS=, read -r err ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 6 --csv "$dir/sky-$m.hdr" "$dir/sky-mis.hdr")"
    python3 -c "import sys; sys.exit(0 if $err <= 0.05 and abs($ratio - 1) <= 0.01 else 1)" ||
        fail "the sky by $m alone: $err from MIS's (6x6 blocks), light ratio $ratio"
    eval "${m}_err=\$err ${m}_ratio=\$ratio"
done
# the Whitted integrator: the harmonics' light and the sun as a
# directional light with its shadows, against the path-traced picture
# (6.7% in 6x6 blocks, light 0.993; without the sun's shadows 21%)
"$BIN/lanray-render" "$dir/sky.scene" --integrator whitted -o "$dir/sky-w.hdr" --quiet >/dev/null 2>&1 || fail "sky (whitted)"
"$BIN/lanray-render" "$dir/sky.scene" --integrator whitted --shadows off -o "$dir/sky-w0.hdr" --quiet >/dev/null 2>&1 ||
    fail "sky (whitted, no shadows)"
IFS=, read -r w_err w_ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 6 --csv "$dir/sky-w.hdr" "$dir/sky-mis.hdr")"
IFS=, read -r w0_err w0_ratio <<<"$("$BIN/lanray-imgdiff" --relative --block 6 --csv "$dir/sky-w0.hdr" "$dir/sky-mis.hdr")"
python3 -c "import sys; sys.exit(0 if $w_err <= 0.1 and abs($w_ratio - 1) <= 0.03 and $w0_err > 2 * $w_err else 1)" ||
    fail "Whitted under the sky: $w_err from the path-traced picture (light $w_ratio), without shadows $w0_err"
# turned 90 degrees, seen by a camera turned 90: the same picture
for r in 0 90; do
    printf 'camera position 0 0 0 yaw %s pitch 10\ntexture sky sky.hdr\nenvironment texture sky rotate %s\n' "$r" "$r" \
        >"$dir/turn$r.scene"
    "$BIN/lanray-render" "$dir/turn$r.scene" --width 32 --height 24 --aa 1 -o "$dir/turn$r.png" --quiet >/dev/null 2>&1 ||
        fail "turn $r"
done
python3 - "$dir/turn0.png" "$dir/turn90.png" <<'PY' || fail "rotate 90 with a camera of yaw 90 should show what rotate 0 shows at yaw 0"
import subprocess, sys
pts = [str(v) for x in range(0, 32, 5) for y in range(0, 24, 5) for v in (x, y)]
a, b = (list(map(int, subprocess.check_output(["python3", "tests/tools/pngpixel.py", f] + pts).split())) for f in sys.argv[1:])
sys.exit(0 if max(abs(p - q) for p, q in zip(a, b)) <= 1 and max(a) - min(a) > 20 else 1)
PY
# bad input
bad() { # SCENE_TEXT WANT WHAT
    printf '%s\n' "$1" >"$dir/bad.scene"
    if "$BIN/lanray-render" "$dir/bad.scene" -o "$dir/bad.png" --quiet >"$dir/bad.log" 2>&1; then
        fail "$3 was accepted"
    fi
    grep -q "$2" "$dir/bad.log" || fail "$3: the error should say '$2': $(cat "$dir/bad.log")"
    [ ! -e "$dir/bad.png" ] || fail "$3 left an image"
}
bad 'environment texture nowhere' "bad.scene:1: unknown texture 'nowhere'" "an unknown texture"
bad $'texture sky sky.hdr\nenvironment texture sky\nenvironment texture sky' "bad.scene:3: a scene has one environment" \
    "a second environment"
bad $'texture sky sky.hdr\nenvironment strength 2' "bad.scene:2:.*texture" "an environment without a texture"
bad $'texture sky sky.hdr\nenvironment texture sky strength -1' "bad.scene:2:.*strength" "a negative strength"
head -c 300 "$dir/sky.hdr" >"$dir/cut.hdr"
bad $'texture sky cut.hdr\nenvironment texture sky' "cut.hdr" "a cut .hdr"
# --environment FILE puts one around any scene (the furnace's own
# environment left out: the same bytes), --environment-strength makes it
# stronger (1: code 255), and either without one is refused
grep -v '^texture\|^environment' "$dir/furnace.scene" >"$dir/bare.scene"
"$BIN/lanray-render" "$dir/bare.scene" --environment "$dir/grey.hdr" --width 32 --height 32 --aa 8 --linear \
    -o "$dir/bare.png" --quiet >/dev/null 2>&1 || fail "--environment"
cmp -s "$dir/bare.png" "$dir/furnace-whitted.png" || fail "--environment FILE should render as the scene's own environment (Whitted)"
"$BIN/lanray-render" "$dir/bare.scene" --environment "$dir/grey.hdr" --integrator path --width 32 --height 32 --aa 8 \
    --linear -o "$dir/bare-path.png" --quiet >/dev/null 2>&1 || fail "--environment (path)"
cmp -s "$dir/bare-path.png" "$dir/furnace-path.png" || fail "--environment FILE should render as the scene's own environment"
"$BIN/lanray-render" "$dir/furnace.scene" --environment-strength 2 --width 32 --height 32 --aa 1 --linear \
    -o "$dir/strong.png" --quiet >/dev/null 2>&1 || fail "--environment-strength"
got=$(python3 tests/tools/pngpixel.py "$dir/strong.png" 16 16 | tr '\n' ' ')
[ "$got" = "255 255 255 " ] || fail "--environment-strength 2 should make the grey furnace's ball white: $got"
"$BIN/lanray-render" "$dir/bare.scene" --environment-rotate 10 -o "$dir/no.png" --quiet >"$dir/no.log" 2>&1 &&
    fail "--environment-rotate without an environment was accepted"
grep -q "the scene has none: give --environment FILE" "$dir/no.log" || fail "--environment-rotate alone: $(cat "$dir/no.log")"
"$BIN/lanray-render" "$dir/bare.scene" --environment "$dir/nothere.hdr" -o "$dir/no.png" --quiet >"$dir/no.log" 2>&1 &&
    fail "a missing --environment file was accepted"
grep -q -- "--environment: .*nothere.hdr" "$dir/no.log" || fail "a missing --environment file: $(cat "$dir/no.log")"
[ ! -e "$dir/no.png" ] || fail "a refused --environment left an image"
# a model's preview under --environment is lit by it alone: in a grey
# furnace the cube's two sides seen alike (its two lights made them differ)
"$BIN/lanray-render" models/cube.obj --environment "$dir/grey.hdr" --width 64 --height 48 --aa 1 --linear \
    -o "$dir/cube.png" --quiet >/dev/null 2>&1 || fail "a preview under --environment"
got=$(python3 tests/tools/pngpixel.py "$dir/cube.png" 20 30 40 30 2 2 | tr '\n' ' ')
set -- $got
[ "$1 $2 $3" = "$4 $5 $6" ] && [ "$7 $8 $9" = "128 128 128" ] ||
    fail "a cube's preview in a grey furnace: its sides and the background should be the furnace's alone: $got"
# a server puts it around its scene as lanray-render does
"$BIN/lanray-render" "$dir/bare.scene" --environment "$dir/sky.hdr" --width 64 --height 64 --aa 1 -o "$dir/bare-sky.png" \
    --quiet >/dev/null 2>&1 || fail "render bare + sky"
start_server barenv "$dir/bare.scene" --environment "$dir/sky.hdr" --port 0 --width 64 --height 64 --frames 1 \
    --wait-clients 1 --verify "$dir/bare-sky.png" --out "$dir/f-barenv"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 2 --once --quiet 2>/dev/null &
pids+=("$!")
for _ in $(seq 300); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.05; done
wait "$server_pid" || fail "a server's --environment frame differs from lanray-render's: $(tail -3 "$dir/barenv.err")"
# the same bytes on every SIMD path and through a server, both integrators
for integ in whitted path; do
    sed "s/integrator path/integrator $integ/" "$dir/sky.scene" >"$dir/sky-$integ.scene"
    "$BIN/lanray-render" "$dir/sky-$integ.scene" --width 64 --height 64 --aa 1 -o "$dir/sky-$integ-1.png" --quiet \
        >/dev/null 2>&1 || fail "render sky ($integ)"
    same_on_simd_paths "$dir/sky-$integ.scene" "$dir/sky-$integ-1.png" 64 64 "the sky ($integ)"
    verify_distributed "sky-$integ" "$dir/sky-$integ.scene" "$dir/sky-$integ-1.png" "under an environment ($integ)"
done
# a mirror ball shrinks a fine checker panorama: at one sample a pixel the
# mip-map (the default filter) shows the checks' mean, close to the picture
# of 16 x 16 samples, where the image read at a point (bilinear) aliases;
# where the camera sees the panorama magnified both read the image itself
python3 tests/tools/envmap.py "$dir/chk.hdr" checker 1024 512 2
printf 'camera position 0 0 4 lookat 0 0 0 fov 40\ntexture sky chk.hdr\nenvironment texture sky\n' >"$dir/chk-bare.scene"
{ cat "$dir/chk-bare.scene"; printf 'material chrome diffuse 0 0 0 reflect 0.9 0.9 0.9\nsphere centre 0 0 0 radius 1 material chrome\n'; } >"$dir/chk.scene"
for f in anisotropic bilinear; do
    "$BIN/lanray-render" "$dir/chk.scene" --width 80 --height 60 --aa 1 --filter $f -o "$dir/chk-$f.png" --quiet \
        >/dev/null 2>&1 || fail "render the mirror ball ($f)"
    "$BIN/lanray-render" "$dir/chk-bare.scene" --width 80 --height 60 --aa 1 --filter $f -o "$dir/bare-$f.png" --quiet \
        >/dev/null 2>&1 || fail "render the bare panorama ($f)"
done
"$BIN/lanray-render" "$dir/chk.scene" --width 80 --height 60 --aa 16 --filter bilinear -o "$dir/chk-ref.png" --quiet \
    >/dev/null 2>&1 || fail "render the mirror ball's reference"
cmp -s "$dir/bare-anisotropic.png" "$dir/bare-bilinear.png" || fail "a magnified panorama should read the image itself under every filter"
mip=$("$BIN/lanray-imgdiff" "$dir/chk-ref.png" "$dir/chk-anisotropic.png" 2>&1 | tail -1 | sed 's/.*rmse \([0-9.]*\).*/\1/')
point=$("$BIN/lanray-imgdiff" "$dir/chk-ref.png" "$dir/chk-bilinear.png" 2>&1 | tail -1 | sed 's/.*rmse \([0-9.]*\).*/\1/')
python3 -c 'import sys; m, p = map(float, sys.argv[1:]); sys.exit(0 if m < 0.5 * p else 1)' "$mip" "$point" ||
    fail "a mirror ball's panorama at one sample: RMSE $mip with the mip-map against $point without, from 16 x 16 samples"
echo "environment: a white ball in a grey furnace shows 0.5 (codes $furnace, path-traced; Whitted's too); the sky by NEE alone and by bounces alone = MIS (6x6 blocks: $nee_err and $bsdf_err, light $nee_ratio and $bsdf_ratio); Whitted's with the sun's shadows $w_err from it (light $w_ratio; without shadows $w0_err); rotate turns it as a yaw; bad input refused by file and line; --environment on the command line as in the file; a mirror ball's panorama at one sample RMSE $mip from 16 x 16 samples with the mip-map, $point without; on every SIMD path and through a server"
