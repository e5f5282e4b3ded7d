#!/usr/bin/env bash
# Texture filtering: a checker floor to the horizon, one sample a pixel,
# against an 8 x 8 reference (it differs from a 16 x 16 one by RMSE
# 0.07-0.09, and the errors below against either by at most 0.03): the default (mip-maps along the footprint)
# has at most a quarter of the error of bilinear lookups without mip-maps
# (what lanray did before: RMSE 5.36 on 2026-11-25) and at most 1.34; a
# textured floor seen in a mirror is filtered too.  The checkerboards of
# models/example.scene and docs/getting-started.md look like checkerboards:
# their texture lines, on a quad that fills the frame, give pixels of the
# texture's own colours with sharp edges, where smooth magnification blurs
# them into dots.
set -u
source tests/tools/server-lib.sh
cp models/checker.ppm "$dir/"
cat >"$dir/horizon.scene" <<'SCENE'
camera position 0 1 0 lookat 0 0.6 -10 fov 60
ambient 1 1 1
background 0.5 0.6 0.8
texture checker checker.ppm
material floor diffuse 1 1 1 texture checker
plane point 0 0 0 normal 0 1 0 material floor uvscale 2
SCENE
render() { "$BIN/lanray-render" "$@" --width 320 --height 240 --quiet >/dev/null 2>"$dir/render.err" || fail "render $*: $(cat "$dir/render.err")"; }
rmse() { "$BIN/lanray-imgdiff" --csv "$1" "$2" | cut -d, -f3; }
check_floor() { # scene, what
    render "$dir/$1.scene" -o "$dir/def.png" --aa 1
    render "$dir/$1.scene" -o "$dir/bil.png" --aa 1 --filter bilinear
    # (the 8 x 8 reference, two thirds of the test's time under a
    # sanitizer, only measures: the sanitizers' pass runs the filters alone)
    [ "$sanitized" = 1 ] && { echo "$2: rendered (not measured under a sanitizer)"; return 0; }
    render "$dir/$1.scene" -o "$dir/ref.png" --aa 8
    local d b
    d=$(rmse "$dir/ref.png" "$dir/def.png")
    b=$(rmse "$dir/ref.png" "$dir/bil.png")
    python3 -c "import sys; d, b = float(sys.argv[1]), float(sys.argv[2]); sys.exit(0 if d <= b / 4 and d <= 1.34 else 1)" "$d" "$b" ||
        fail "$2: RMSE $d with the default filter, $b bilinear: not a quarter of it or not at most 1.34"
    echo "$2: RMSE $d (bilinear $b)"
}
check_floor horizon "a checker floor to the horizon"
# the same floor seen in a mirror wall that fills the frame
{
    sed 's/^camera position 0 1 0 /camera position 0 1 4 /' "$dir/horizon.scene"
    echo "material mirror reflect 1 1 1"
    echo "plane point 0 0 -1 normal 0 0 1 material mirror"
} >"$dir/mirror.scene"
check_floor mirror "the floor in a mirror" 2>&1 | sed 's/^/  /'
[ "${PIPESTATUS[0]}" = 0 ] || exit 1
# a procedural checker (material checker) to the horizon: averaged over
# each sample's footprint (a box on each axis), not read at a point (what
# --filter nearest keeps, and all there was before 2026-11-29: RMSE 31.1
# of a 16 x 16 reference at one sample a pixel, moire to the horizon,
# where the filtered floor is 6.0); near squares keep their edges (the
# near floor's row 230: both colours, few pixels between)
cat >"$dir/solid.scene" <<'SCENE'
camera position 0 1 0 lookat 0 0.6 -10 fov 60
ambient 1 1 1
background 0.5 0.6 0.8
material floor diffuse 1 1 1 checker 0.1 0.1 0.1 checker_size 0.5
plane point 0 -0.01 0 normal 0 1 0 material floor
SCENE
render "$dir/solid.scene" -o "$dir/sdef.png" --aa 1
render "$dir/solid.scene" -o "$dir/snear.png" --aa 1 --filter nearest
if [ "$sanitized" != 1 ]; then
    render "$dir/solid.scene" -o "$dir/sref.png" --aa 8
    d=$(rmse "$dir/sref.png" "$dir/sdef.png")
    n=$(rmse "$dir/sref.png" "$dir/snear.png")
    python3 -c "import sys; d, n = float(sys.argv[1]), float(sys.argv[2]); sys.exit(0 if d <= n / 3 and d <= 8 else 1)" "$d" "$n" ||
        fail "a procedural checker to the horizon: RMSE $d filtered, $n at a point: not a third of it or not at most 8"
    echo "a procedural checker to the horizon: RMSE $d (at a point $n)"
fi
edge=$(python3 tests/tools/pngpixel.py "$dir/sdef.png" $(seq -s ' 230 ' 0 8 319) 230 | awk '{print $1}' | tr '\n' ' ')
python3 -c "import sys; v = [int(x) for x in sys.argv[1:]]; sys.exit(0 if min(v) < 100 and max(v) > 250 and sum(1 for x in v if 100 <= x <= 250) <= len(v) // 4 else 1)" $edge ||
    fail "the near squares of a procedural checker are not sharp: codes $edge"
# the checkerboards users copy: the texture line of each, on a quad filling the frame
crisp() { # scene: the share of pixels within 6 codes of a texel colour of checker.ppm
    render "$1" -o "$dir/quad.png" --aa 1 >/dev/null
    python3 - "$dir/quad.png" "$dir/checker.ppm" <<'PY'
import subprocess, sys
vals = open(sys.argv[2]).read().split("\n", 4)[4].split()
texels = [tuple(int(v) for v in vals[i:i + 3]) for i in range(0, len(vals), 3)]
pts = [str(c) for y in range(2, 240, 4) for x in range(2, 320, 4) for c in (x, y)]
out = subprocess.run(["python3", "tests/tools/pngpixel.py", sys.argv[1]] + pts, capture_output=True, text=True, check=True).stdout
px = [tuple(int(v) for v in l.split()) for l in out.splitlines() if l.strip()]
near = sum(1 for p in px if any(max(abs(a - b) for a, b in zip(p, t)) <= 6 for t in texels))
print("%.3f" % (near / len(px)))
PY
}
for src in models/example.scene docs/getting-started.md; do
    line=$(grep -m1 '^texture .*checker.ppm' "$src" | sed 's|[^ ]*checker.ppm|checker.ppm|')
    [ -n "$line" ] || fail "$src has no checker texture"
    name=$(awk '{print $2}' <<<"$line")
    {
        echo "camera position 0 0 2.2 lookat 0 0 0 fov 60"
        echo "ambient 1 1 1"
        echo "$line"
        echo "material m diffuse 1 1 1 texture $name"
        echo "triangle vertices -2 -1.5 0  2 -1.5 0  2 1.5 0 uv 0 0 1 0 1 1 material m"
        echo "triangle vertices -2 -1.5 0  2 1.5 0  -2 1.5 0 uv 0 0 1 1 0 1 material m"
    } >"$dir/quad.scene"
    share=$(crisp "$dir/quad.scene")
    python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) >= 0.9 else 1)" "$share" ||
        fail "$src: the checkerboard is not crisp: $share of its pixels show a texel's colour"
    sed -i "s/ closest\$//" "$dir/quad.scene" # smooth magnification blurs it: the check can fail
    blurred=$(crisp "$dir/quad.scene")
    python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 0.5 else 1)" "$blurred" ||
        fail "$src: a smoothly magnified checkerboard passed as crisp ($blurred)"
done
echo "filtering: checker floors to the horizon and in a mirror at a quarter of bilinear's error or less, a procedural one at a third of a point's; the checkerboards of example.scene and getting-started are crisp"
