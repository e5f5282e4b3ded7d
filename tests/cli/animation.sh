#!/usr/bin/env bash
# The server's animation (--rotate, Space in the window) turns every model
# instance between frames, never during one: frame k of a server run with
# --rotate D shows the instances turned by (k-1) x D, as lanray-render
# renders the scene with that rotation, byte for byte (the moving frames'
# history left out: --whitted-temporal 0; tests/cli/history.sh serves
# turning frames with it), and as lanray-render --server-frame k --rotate D
# turns them.
set -u
source tests/tools/server-lib.sh
cat >"$dir/turn.scene" <<SCENE
camera position 0 1.5 4 lookat 0 0.3 0 fov 50
material clay diffuse 0.8 0.6 0.3 specular 0.3 0.3 0.3 shininess 20
plane point 0 -0.5 0 normal 0 1 0
model cube $PWD/models/cube.obj
instance cube rotate 0 ANGLE 0 material clay
light point position 2 4 3
SCENE
for a in 0 15 30; do
    sed "s/ANGLE/$a/" "$dir/turn.scene" >"$dir/turn-$a.scene"
    "$BIN/lanray-render" "$dir/turn-$a.scene" --aa 1 --width 64 --height 48 -o "$dir/ref-$a.png" --quiet >/dev/null ||
        fail "lanray-render $a"
done
start_server anim "$dir/turn-0.scene" --port 0 --width 64 --height 48 --frames 3 --wait-clients 1 --rotate 15 \
    --whitted-temporal 0 --out "$dir/f"
"$BIN/lanray-client" "127.0.0.1:$port" --threads 2 --once --quiet 2>"$dir/client.err" &
pids+=("$!")
server_done 120 anim
wait "$server_pid" || fail "the server exited $?"
for k in 1 2 3; do
    a=$(((k - 1) * 15))
    cmp -s "$dir/f/frame-0000$k.png" "$dir/ref-$a.png" || fail "frame $k is not the scene turned by $a degrees"
    "$BIN/lanray-render" "$dir/turn-0.scene" --aa 1 --width 64 --height 48 --server-frame $k --rotate 15 \
        --whitted-temporal 0 -o "$dir/sf-$k.png" --quiet >/dev/null || fail "lanray-render --server-frame $k --rotate 15"
    cmp -s "$dir/sf-$k.png" "$dir/ref-$a.png" || fail "lanray-render --server-frame $k --rotate 15 is not the scene turned by $a degrees"
done
cmp -s "$dir/ref-0.png" "$dir/ref-15.png" && fail "turning the cube changed nothing: the test cannot fail"
echo "animation: frames 1 to 3 are the instances turned by 0, 15 and 30 degrees, as lanray-render draws them (and as its --server-frame --rotate turns them)"
