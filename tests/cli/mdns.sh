#!/usr/bin/env bash
# The farm finds itself: a server started with --announce is seen by a
# client started without an address, which connects and renders frames
# equal to lanray-render's; with two servers the client lists both and
# exits 1; a farm of another protocol version is ignored; without a daemon
# the client says so and the server serves anyway.  Everything runs in a
# network namespace made here (a veth pair inside it, nothing leaves the
# machine) with a private D-Bus and avahi-daemon (in a mount namespace of
# its own, so that a system daemon, if any, is left alone).  CLIENT: the
# client that looks for the farm (bin's; tests/cli/deb.sh passes the one its
# package installed, with MDNS_ONLY_FIND=1 to stop once it has joined).
set -u
[ -n "${MDNS_TRACE:-}" ] && set -x
BIN=${BIN:-bin}
dir=$(mktemp -d)
ns=lrmdns$$
pids=()
cleanup() {
    # what runs in the namespace first: a server started through in_ns &
    # is a grandchild, which killing the subshell in pids leaves running
    for p in $(ip netns pids "$ns" 2>/dev/null); do kill "$p" 2>/dev/null; done
    for _ in $(seq 40); do [ -z "$(ip netns pids "$ns" 2>/dev/null)" ] && break; sleep 0.05; done
    for p in $(ip netns pids "$ns" 2>/dev/null); do kill -9 "$p" 2>/dev/null; done
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
    wait 2>/dev/null
    ip netns del "$ns" 2>/dev/null
    rm -rf "$dir"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; tail -5 "$dir"/*.err 2>/dev/null; exit 1; }
for t in ip dbus-daemon avahi-daemon avahi-publish avahi-browse unshare; do
    command -v $t >/dev/null || fail "$t is needed (make deps installs it)"
done
[ "$(id -u)" = 0 ] || { echo "mdns: not root: the network namespace cannot be made; skipped"; exit 0; }
ip netns add "$ns" || fail "ip netns add"
ip -n "$ns" link set lo up
ip -n "$ns" link add d0 type veth peer name d1
ip -n "$ns" link set d1 up
ip -n "$ns" link set d0 multicast on up
ip -n "$ns" addr add 10.216.0.1/24 dev d0
in_ns() { ip netns exec "$ns" env DBUS_SYSTEM_BUS_ADDRESS="unix:path=$dir/bus" "$@"; }
cat >"$dir/bus.conf" <<CONF
<busconfig>
  <type>system</type>
  <listen>unix:path=$dir/bus</listen>
  <auth>EXTERNAL</auth>
  <policy context="default">
    <allow user="*"/>
    <allow own="*"/>
    <allow send_destination="*" eavesdrop="true"/>
    <allow eavesdrop="true"/>
  </policy>
</busconfig>
CONF
dbus-daemon --config-file="$dir/bus.conf" --nofork --nopidfile 2>"$dir/dbus.err" &
pids+=($!)
for _ in $(seq 50); do [ -S "$dir/bus" ] && break; sleep 0.1; done
[ -S "$dir/bus" ] || fail "the private D-Bus did not start"
cat >"$dir/avahi.conf" <<CONF
[server]
use-ipv4=yes
use-ipv6=no
allow-interfaces=d0
enable-dbus=yes
[publish]
publish-hinfo=no
publish-workstation=no
CONF
# the client without a daemon: says so, exits 1
out=$(in_ns "$BIN/lanray-client" --once 2>&1) && fail "a client found a farm with no daemon: $out"
grep -q "no way to look for one: mDNS" <<<"$out" || fail "no daemon: the client said: $out"
# the server without a daemon: says so, and serves a client given its address
in_ns "$BIN/lanray-server" --listen 10.216.0.1 --port 0 --token mdns-test --announce yes --width 16 --height 8 \
    --headless --discard --frames 1 >"$dir/lone.log" 2>"$dir/lone.err" &
lone=$!
for _ in $(seq 100); do port=$(sed -n 's/.*listening on .*:\([0-9]*\) (.*/\1/p' "$dir/lone.log"); [ -n "$port" ] && break; sleep 0.05; done
[ -n "$port" ] || fail "no daemon: the server did not start"
in_ns env LANRAY_TOKEN=mdns-test "$BIN/lanray-client" "10.216.0.1:$port" --once --threads 1 --quiet 2>"$dir/lone-client.err" ||
    fail "no daemon: a client with the address was not served"
wait "$lone" || fail "no daemon: the server failed"
grep -q "not announced on the LAN: mDNS" "$dir/lone.err" || fail "no daemon: the server did not say so"
in_ns unshare -m sh -c "mount -t tmpfs none /run && exec avahi-daemon --no-chroot --no-drop-root --no-rlimits -f $dir/avahi.conf" \
    >"$dir/avahi.log" 2>"$dir/avahi.err" &
pids+=($!)
for _ in $(seq 100); do grep -qs "Server startup complete" "$dir/avahi.err" && break; sleep 0.1; done
grep -q "Server startup complete" "$dir/avahi.err" || fail "avahi-daemon did not start"

W=64 H=48
"$BIN/lanray-render" --width $W --height $H --aa 1 -o "$dir/ref.png" --quiet >/dev/null || fail "reference"
# serve NAME FRAMES: a server on the namespace's address, announced, that
# ends after FRAMES frames (0: serves on); sets last
serve() {
    in_ns "$BIN/lanray-server" --listen 10.216.0.1 --port 0 --token mdns-test --announce yes --width $W --height $H \
        --headless --frames "$2" --verify "$dir/ref.png" --out "$dir/$1" >"$dir/$1.log" 2>"$dir/$1.err" &
    pids+=($!)
    last=$!
    for _ in $(seq 100); do grep -qs "announced on the LAN" "$dir/$1.err" && return 0; sleep 0.05; done
    fail "$1 was not announced"
}
# a farm of another protocol version, which the client must not take
in_ns avahi-publish -s "lanray old" _lanray._tcp 7999 proto=9 --sub _v9._sub._lanray._tcp >/dev/null 2>&1 &
pids+=($!)
for _ in $(seq 50); do in_ns avahi-browse -t -p _lanray._tcp 2>/dev/null | grep -q 'lanray\\032old' && break; sleep 0.1; done
in_ns avahi-browse -t -p _lanray._tcp 2>/dev/null | grep -q 'lanray\\032old' || fail "the farm of protocol 9 was not announced"
serve one 3
one=$last
out=$(in_ns env LANRAY_TOKEN=mdns-test timeout 60 "${CLIENT:-$BIN/lanray-client}" --once --threads 1 2>&1)
wait "$one" || fail "the server ended with an error: $(tail -3 "$dir/one.err")"
grep -q "found lanray on .* at 10.216.0.1:[0-9]* (mDNS)" <<<"$out" || fail "the client did not find the server: $out"
grep -q "verify frames=[1-9][0-9]* wrong_frames=0 " "$dir/one.log" || fail "no frames, or wrong ones: $(grep verify "$dir/one.log")"
echo "mdns: a client without an address found the server ($(grep -o 'found .*' <<<"$out" | head -1)) and rendered $(sed -n 's/.*verify frames=\([0-9]*\).*/\1/p' "$dir/one.log") frames equal to lanray-render's; a farm of protocol 9 ignored"
[ -n "${MDNS_ONLY_FIND:-}" ] && exit 0 # tests/cli/deb.sh: the installed client found and joined the farm
serve two 0
serve three 0
out=$(in_ns timeout 20 "$BIN/lanray-client" --once 2>&1) && fail "two farms: the client picked one"
grep -q "2 farms on the LAN" <<<"$out" && [ "$(grep -c '^  10.216.0.1:' <<<"$out")" = 2 ] || fail "two farms: $out"
grep -q "token needed" <<<"$out" || fail "the list does not say a token is needed: $out"
echo "mdns: with two servers the client lists both and exits 1; without a daemon it says so"
exit 0
