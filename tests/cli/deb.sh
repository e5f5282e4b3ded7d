#!/usr/bin/env bash
# The Debian package (tools/dist/make-deb, make deb; lintian left to make
# deb): it holds every file make install installs, installs into a clean
# root made here (dpkg --root, no maintainer scripts to run), and the client
# it installed finds a server announced on a LAN in a network namespace
# (tests/cli/mdns.sh with that client) and joins it, rendering frames equal
# to lanray-render's.
set -u
BIN=${BIN:-bin}
# packaging is checked on the plain build: a package of the sanitizers'
# binaries adds nothing that mdns.sh does not run under them already
case "$BIN" in *asan* | *tsan*) echo "deb: checked with the plain build only"; exit 0 ;; esac
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
for t in dpkg dpkg-deb dpkg-shlibdeps help2man; do
    command -v $t >/dev/null || fail "$t is needed (make deps installs it)"
done
DEB_OUT="$dir" LINTIAN=0 BIN="$BIN" bash tools/dist/make-deb >"$dir/make-deb.log" 2>&1 || { cat "$dir/make-deb.log"; fail "make-deb"; }
deb=$(ls "$dir"/lanray_*.deb)
[ -f "$deb" ] || fail "no package"
# every file make install installs is in the package, at the same path
make --no-print-directory install DESTDIR="$dir/inst" PREFIX=/usr BIN="$BIN" >/dev/null 2>&1 || fail "make install"
(cd "$dir/inst" && find . -type f | sed 's|^\./|/|' | sort) >"$dir/installed"
dpkg-deb --contents "$deb" | awk '$1 !~ /^d/ { sub(/^\./, "", $6); print $6 }' | sort >"$dir/packaged"
missing=$(comm -23 "$dir/installed" "$dir/packaged")
[ -z "$missing" ] || fail "installed but not packaged: $missing"
# into a clean root: dpkg's own database there, nothing else
root="$dir/root"
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates" "$root/var/lib/dpkg/triggers"
: >"$root/var/lib/dpkg/status"
: >"$root/var/lib/dpkg/available"
dpkg --root="$root" --force-not-root --force-depends --force-script-chrootless --log=/dev/null -i "$deb" \
    >"$dir/dpkg.log" 2>&1 || { cat "$dir/dpkg.log"; fail "dpkg -i into a clean root"; }
grep -q "^Status: install ok installed" "$root/var/lib/dpkg/status" || fail "dpkg does not list the package as installed"
for p in lanray-server lanray-client lanray-render; do
    "$root/usr/bin/$p" --version >/dev/null || fail "the installed $p does not run"
done
n=$(grep -c . "$dir/packaged")
out=$(CLIENT="$root/usr/bin/lanray-client" MDNS_ONLY_FIND=1 BIN="$BIN" bash tests/cli/mdns.sh 2>&1) ||
    fail "the installed client did not find and join the farm: $out"
grep -q "skipped" <<<"$out" && { echo "deb: $n files packaged, installed into a clean root; $out"; exit 0; }
echo "deb: $n files, all that make install installs; dpkg installed it into a clean root; its client $(grep -o 'found the server.*' <<<"$out" | head -1)"
