#!/usr/bin/env bash
# lanray against an independent tracer: tools/bench/embree_ref traces the same
# camera and shadow rays through Intel Embree and shades them alike, so the
# two images may differ only where a ray grazes a shared edge or the shadow
# terminator.  The scene is an extreme one for shadow-ray offsets: a bumpy
# closed mesh (9,000 triangles, self-shadowing) scaled down to 0.05 and seen
# from 68 times its size away, so that the error of a hit point taken as
# o + t*d is far larger than the triangle's own; a reference that did that
# showed acne on 12% of the pixels, and so would lanray with it.
set -u
BIN=${BIN:-bin}
EMBREE_REF=${EMBREE_REF:-${BUILD:-build/float}/tools/bench/embree_ref}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
[ -x "$EMBREE_REF" ] || fail "$EMBREE_REF not built"
# Embree computes in float: a double build's tighter error bounds do not
# cover its hit points, so its image shows acne that says nothing of lanray's
case "$("$BIN/lanray-render" --version)" in
*double*) echo "embree: a double-precision build; Embree is float, nothing to compare"; exit 0 ;;
esac
awk 'BEGIN { pi = 3.14159265358979; U = 96; V = 48
    for (j = 0; j <= V; j++) for (i = 0; i < U; i++) {
        th = pi * j / V; ph = 2 * pi * i / U; r = 1 + 0.12 * sin(5 * th) * sin(4 * ph) + 0.05 * sin(11 * ph)
        printf "v %.6f %.6f %.6f\n", r * sin(th) * cos(ph), r * cos(th), r * sin(th) * sin(ph) }
    for (j = 0; j < V; j++) for (i = 0; i < U; i++) {
        a = j * U + i + 1; b = j * U + (i + 1) % U + 1; c = a + U; d = b + U
        if (j > 0) print "f", a, c, b
        if (j < V - 1) print "f", b, c, d } }' >"$dir/blob.obj"
"$BIN/obj2tmd" "$dir/blob.obj" "$dir/blob.tmd" >/dev/null || fail "obj2tmd"
cat >"$dir/blob.scene" <<'SCENE'
camera position 0 0.4 3.4 lookat 0 0 0 fov 3
ambient 0.1 0.1 0.1
material clay diffuse 0.8 0.75 0.7 specular 0.3 0.3 0.3 shininess 20
model blob blob.tmd
instance blob scale 0.05 material clay
light point position 2 3 4 intensity 0.9
SCENE
"$BIN/lanray-render" "$dir/blob.scene" --width 320 --height 240 --threads 2 --aa 1 -o "$dir/ours.png" --quiet >/dev/null || fail "lanray-render"
"$EMBREE_REF" "$dir/blob.scene" --width 320 --height 240 --threads 2 -o "$dir/embree.png" >/dev/null || fail "embree_ref"
IFS=, read -r maxd differ rmse psnr ssim < <("$BIN/lanray-imgdiff" --csv "$dir/ours.png" "$dir/embree.png")
echo "lanray against Embree: $differ of 76800 pixels differ (max $maxd), SSIM $ssim"
# 4 differ as built; 0.05% is 38
[ "$differ" -le 38 ] || fail "$differ pixels differ from Embree's image (at most 38)"
awk -v s="$ssim" 'BEGIN { exit !(s >= 0.999) }' || fail "SSIM $ssim against Embree's image (at least 0.999)"

# every ray class, the same rays through both (tools/bench/rayclass): the
# built-in default scene (spheres, a plane, a mesh, scene triangles) and
# the blob; hit or miss and the distance must agree on nearly every ray
RAYCLASS=${RAYCLASS:-${BUILD:-build/float}/tools/bench/rayclass}
[ -x "$RAYCLASS" ] || fail "$RAYCLASS not built"
for scene in "" "$dir/blob.scene"; do
    out=$("$RAYCLASS" $scene --width 96 --height 72 --repeat 1 --threads 2) || fail "rayclass ${scene:-default}"
    [ "$(wc -l <<<"$out")" -eq 6 ] || fail "rayclass ${scene:-default}: $out"
    low=$(awk '$NF < 99.9 || $5 < 100 { print $3 " " $NF "% of " $5 }' <<<"$out")
    [ -z "$low" ] || fail "rayclass ${scene:-default}: lanray and Embree disagree: $low"
done
echo "rayclass: lanray and Embree agree on every class of ray (camera, shadow to point and area lights, mirrored, refracted, diffuse), default scene and blob"
