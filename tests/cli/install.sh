#!/usr/bin/env bash
# make install into a staging root (DESTDIR, PREFIX=/usr): the programs run
# from there, the client's systemd unit starts the installed client with
# its settings file, the Avahi file names this protocol version, a farm's
# own settings survive a second install, and make uninstall takes the
# programs away and leaves the settings.
set -u
BIN=${BIN:-bin}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
root="$dir/root"
make --no-print-directory install DESTDIR="$root" PREFIX=/usr BIN="$BIN" >"$dir/log" 2>&1 || { cat "$dir/log"; fail "make install"; }
for p in lanray-server lanray-client lanray-render obj2tmd lanray-imgdiff; do
    [ -x "$root/usr/bin/$p" ] || fail "$p not installed"
    "$root/usr/bin/$p" --version >/dev/null || fail "$p --version"
done
unit="$root/lib/systemd/system/lanray-client.service"
[ -r "$unit" ] || fail "no systemd unit"
grep -q '^ExecStart=/usr/bin/lanray-client $LANRAY_SERVER --threads ${LANRAY_THREADS}' "$unit" || fail "the unit does not start the installed client: $(grep ExecStart "$unit")"
grep -q '^EnvironmentFile=-/etc/default/lanray-client$' "$unit" || fail "the unit does not read /etc/default/lanray-client"
grep -q '^Restart=on-failure$' "$unit" && grep -q '^Nice=' "$unit" || fail "the unit neither restarts nor is nice"
! grep -q '@' "$unit" || fail "a placeholder left in the unit"
if command -v systemd-analyze >/dev/null; then
    sed "s|/usr/bin/lanray-client|$root/usr/bin/lanray-client|" "$unit" >"$dir/lanray-client.service"
    systemd-analyze verify "$dir/lanray-client.service" 2>"$dir/verify" || true
    ! grep -qi "error\|invalid\|unknown" "$dir/verify" || fail "systemd-analyze: $(cat "$dir/verify")"
fi
proto=$(sed -n 's/^#define PROTO_VERSION \([0-9]*\)u.*/\1/p' common/net/msg.h)
avahi="$root/etc/avahi/services/lanray.service"
grep -q "<subtype>_v$proto._sub._lanray._tcp</subtype>" "$avahi" && grep -q "<txt-record>proto=$proto</txt-record>" "$avahi" ||
    fail "the Avahi file does not name protocol $proto"
python3 -c "import sys, xml.dom.minidom; xml.dom.minidom.parse(sys.argv[1])" "$avahi" 2>/dev/null || fail "the Avahi file is not XML"
[ -r "$root/usr/share/doc/lanray/farm.md" ] || fail "no farm guide among the docs"
grep -q '^LANRAY_SERVER=' "$root/etc/default/lanray-client" || fail "no client settings file"
# a farm's settings stay through a second install and an uninstall
echo "LANRAY_SERVER=render-boss:7878" >"$root/etc/default/lanray-client"
make --no-print-directory install DESTDIR="$root" PREFIX=/usr BIN="$BIN" >/dev/null 2>&1 || fail "second make install"
grep -q "render-boss" "$root/etc/default/lanray-client" || fail "a second install overwrote the client's settings"
make --no-print-directory uninstall DESTDIR="$root" PREFIX=/usr >/dev/null 2>&1 || fail "make uninstall"
[ ! -e "$root/usr/bin/lanray-client" ] && [ ! -e "$unit" ] || fail "make uninstall left the programs or the unit"
grep -q "render-boss" "$root/etc/default/lanray-client" || fail "make uninstall took the client's settings"
echo "install: programs, docs, systemd unit (ExecStart /usr/bin/lanray-client), Avahi file for protocol $proto; settings kept through reinstall and uninstall"
