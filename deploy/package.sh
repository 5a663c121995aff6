#!/usr/bin/env bash
# Builds the gale .deb (deploy/package.cmake) in build/, lints it (fails on any lintian
# error), and with --install also installs it on this machine, verifies the units with
# systemd-analyze, starts the installed gale-server as its unit would (under systemd when
# it runs here, else by hand), asks /healthz, purges the package and lists anything it
# left behind (fails when there is any). Needs root for --install.
# Usage: deploy/package.sh [--install]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)" >/dev/null
(cd build && rm -f gale_*.deb && cpack -G DEB >/dev/null)
deb="$(ls build/gale_*_amd64.deb)"
echo "== $deb"
dpkg-deb -I "$deb" | sed -n '/Package:/p;/Version:/p;/Depends:/p'
echo "== lintian"
lint="$(lintian --tag-display-limit 0 "$deb" 2>&1 | grep -v 'root privileges' || true)"
echo "${lint:-(nothing)}"
if grep -q '^E:' <<<"$lint"; then
    echo "package.sh: lintian errors" >&2
    exit 1
fi
[ "${1:-}" = "--install" ] || exit 0
leftovers() {
    find /etc /lib/systemd /usr/lib/systemd /usr/bin /usr/share/doc /var/lib/systemd /var/cache \
        /var/lib/private \
        -name '*gale*' ! -name 'galera*' ! -name '*galeri*' 2>/dev/null | sort
}
echo "== dpkg -i"
dpkg -i "$deb" | tail -2
ls -l /etc/gale
echo "== systemd-analyze verify"
systemd-analyze verify /lib/systemd/system/gale-server.service \
    /lib/systemd/system/gale-relay.service /lib/systemd/system/nats-server.service
echo "(clean)"
systemd-analyze security --offline=yes /lib/systemd/system/gale-server.service | tail -1
echo "== start"
port=18080
if [ -d /run/systemd/system ]; then
    systemctl start gale-server.service
    systemctl status --no-pager gale-server.service | head -5
    port=8080
    pid=""
else
    echo "(systemd is not running here: the unit's command by hand)"
    tmp="$(mktemp -d)"
    /usr/bin/gale-server --cache "$tmp" --kiosk-token-file /etc/gale/kiosk-token \
        --port "$port" --iface 127.0.0.1 >"$tmp/out" 2>"$tmp/log" &
    pid=$!
fi
for _ in $(seq 1 600); do
    curl -sf "http://127.0.0.1:$port/healthz" >/dev/null 2>&1 && break
    sleep 0.2
done
echo "/healthz: $(curl -s "http://127.0.0.1:$port/healthz")"
[ -n "$pid" ] && { kill -TERM "$pid"; wait "$pid" || true; rm -rf "$tmp"; }
echo "== dpkg --purge"
dpkg --purge gale | tail -1
left="$(leftovers)"
echo "left behind: ${left:-nothing}"
[ -z "$left" ]
