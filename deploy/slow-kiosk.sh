#!/usr/bin/env bash
# A kiosk on a slow renderer, watched (server/SERVER.md "Slow readers"): gale-server on the
# town block, a windowed `gale-client --role kiosk --size 1280x720` under Xvfb (llvmpipe:
# a frame a second or fewer) with its token from a file, the dial at SPEED m/s (default
# 50) by gale-ctl once it draws. Every 10 s prints the server's WebSocket connections so
# far, kiosks connected, readers decimated, rate lowerings and 4008 closes; near the end
# the kiosk writes a screenshot (SIGUSR1) into OUT. Any further arguments go to the client.
# Usage: deploy/slow-kiosk.sh OUT [SECONDS] [SPEED] [client args...]
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || [ "$1" = --help ] || [ "$1" = -h ]; then
    echo "usage: deploy/slow-kiosk.sh OUT [SECONDS] [SPEED] [client args...]"
    sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
    [ $# -ge 1 ] && exit 0 || exit 2
fi
out="$(mkdir -p "$1" && cd "$1" && pwd)"
secs="${2:-300}"
speed="${3:-50}"
shift $(($# < 3 ? $# : 3))
build="$(cd "${GALE_BUILD:-build}" && pwd)"
for b in server/gale-server client/gale-client client/gale-ctl; do
    if [ ! -x "$build/$b" ]; then
        echo "slow-kiosk: build first (deploy/build.sh); needs $build/$b" >&2
        exit 2
    fi
done
command -v Xvfb >/dev/null || { echo "slow-kiosk: needs Xvfb" >&2; exit 2; }
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
}
trap cleanup EXIT
umask 077
echo "slow-kiosk-$$-$RANDOM" > "$out/token"
port=$((20000 + RANDOM % 20000))
disp=$((200 + RANDOM % 300))
"$build/server/gale-server" --port "$port" --kiosk-token-file "$out/token" --kiosk-idle 86400 \
    > "$out/server.log" 2>&1 &
pids+=($!)
for _ in $(seq 600); do curl -sf "http://127.0.0.1:$port/healthz" >/dev/null && break; sleep 0.2; done
Xvfb ":$disp" -screen 0 1280x1024x24 >/dev/null 2>&1 &
pids+=($!)
sleep 1
(cd "$out" && DISPLAY=":$disp" exec "$build/client/gale-client" --url "ws://127.0.0.1:$port" \
    --role kiosk --size 1280x720 --token-file "$out/token" --attract 86400 "$@" \
    > "$out/client.out" 2> "$out/client.log") &
client_pid=$!
pids=("$client_pid" "${pids[@]}")
for _ in $(seq 1500); do grep -q "receiving state" "$out/client.log" && break; sleep 0.2; done
"$build/client/gale-ctl" --url "ws://127.0.0.1:$port" --token-file "$out/token" wind \
    --speed "$speed" > "$out/ctl.log" 2>&1
row() { curl -s "http://127.0.0.1:$port/metrics" | awk -v k="$1" '$1 == k { print $2 }'; }
t0=$(date +%s)
shot=0
echo "t_s connections kiosks decimated_now decimations closed_4008 load1" | tee "$out/samples.txt"
while :; do
    t=$(($(date +%s) - t0))
    echo "$t $(row gale_connections_total) $(row 'gale_clients{role="kiosk"}')" \
        "$(row gale_readers_decimated) $(row gale_decimations_total)" \
        "$(row gale_laggards_closed_total) $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$out/samples.txt"
    if [ "$shot" = 0 ] && [ "$t" -ge $((secs - 15)) ]; then
        kill -USR1 "$client_pid" 2>/dev/null || true
        shot=1
    fi
    [ "$t" -ge "$secs" ] && break
    sleep 10
done
echo "(the connections count gale-ctl's one besides the kiosk's)"
kill -TERM "$client_pid" 2>/dev/null || true
wait "$client_pid" 2>/dev/null || true
grep "frames ok" "$out/client.log" || true
ls "$out"/gale-*.png 2>/dev/null || echo "slow-kiosk: no screenshot (the client drew no frame after the signal)"
