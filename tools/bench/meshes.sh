# meshes.sh - what the renderer benchmarks share (sourced): the meshes by
# name and their scenes, framed as the shared Embree/POV-Ray harness frames
# them.  Needs MODELS, SHARED_BENCH and CACHE set.

mesh_obj() {
    case $1 in
    sphere1m)
        local obj=$CACHE/sphere1m.obj
        if [ ! -s "$obj" ]; then
            [ -r "$SHARED_BENCH/meshgen.py" ] || { echo "bench: $SHARED_BENCH/meshgen.py not found" >&2; return 1; }
            python3 "$SHARED_BENCH/meshgen.py" --tris 1000000 --seed 1 -o "$obj.tmp" >/dev/null 2>&1 && mv "$obj.tmp" "$obj"
        fi
        echo "$obj" ;;
    *) echo "$MODELS/$1.obj" ;;
    esac
}

# scene file for a .tmd, framed by the shared harness's camera
write_scene() { # obj tmd scene
    local cam
    cam=$(python3 "$SHARED_BENCH/scene.py" camera "$1")
    local eye at light
    eye=$(sed 's/.*--eye \([^ ]*\).*/\1/' <<<"$cam" | tr , ' ')
    at=$(sed 's/.*--at \([^ ]*\).*/\1/' <<<"$cam" | tr , ' ')
    light=$(sed 's/.*--light \([^ ]*\).*/\1/' <<<"$cam" | tr , ' ')
    cat >"$3" <<SCENE
camera position $eye lookat $at fov 45
ambient 0.1 0.1 0.1
material clay diffuse 0.8 0.75 0.7 specular 0.3 0.3 0.3 shininess 20
model mesh $(basename "$2")
instance mesh material clay
light point position $light intensity 0.9
SCENE
}

