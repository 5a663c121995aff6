#!/usr/bin/env bash
# Pictures of a tree falling, caught live (client/CLIENT.md "Pictures of a fall, live"): gale-server
# on SCENE (default configs/scenes/clearing.json, a few trees in the open) in calm, a
# headless gale-client that frames the first fall it sees begin (--fall-shots), and gale-ctl
# dialling SPEED m/s (default 45: pines uproot, oaks and palms stand; server/PHYSICS.md
# "Storm damage") once the client draws. Writes OUT-fall-S.Ss.png for each time of TIMES
# (default 0.5,1.5,2.5,3.5,6) after the stem gave way and OUT.png, the last frame.
# Usage: deploy/live-fall.sh OUT [SPEED] [SCENE] [TIMES]
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || [ "$1" = --help ] || [ "$1" = -h ]; then
    echo "usage: deploy/live-fall.sh OUT [SPEED] [SCENE] [TIMES]"
    sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'
    [ $# -ge 1 ] && exit 0 || exit 2
fi
out="$1"
speed="${2:-45}"
scene="${3:-configs/scenes/clearing.json}"
times="${4:-0.5,1.5,2.5,3.5,6}"
build="${GALE_BUILD:-build}"
for b in server/gale-server client/gale-client client/gale-ctl; do
    if [ ! -x "$build/$b" ]; then
        echo "live-fall: build first (deploy/build.sh); needs $build/$b" >&2
        exit 2
    fi
done
work="$(mktemp -d)"
server_pid=""
client_pid=""
cleanup() {
    [ -n "$client_pid" ] && kill "$client_pid" 2>/dev/null || true
    [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null || true
    wait 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT
echo "live-fall-$$-$RANDOM" > "$work/token"
port=$((20000 + RANDOM % 20000))
"$build/server/gale-server" --config "$scene" --port "$port" --kiosk-token-file "$work/token" \
    --scenario configs/scenarios/calm.json > "$work/server.log" 2>&1 &
server_pid=$!
for _ in $(seq 100); do
    grep -q "listening on" "$work/server.log" && break
    sleep 0.2
done
client=("$build/client/gale-client" --url "ws://127.0.0.1:$port" --headless --size 800x450
        --storm-fx off --frames 100000 --wait 60 --fall-shots "$times" --screenshot "$out.png")
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
    client=(xvfb-run -a -s "-screen 0 1280x1024x24" "${client[@]}")
fi
"${client[@]}" > "$work/client.out" 2> "$work/client.err" &
client_pid=$!
for _ in $(seq 300); do
    grep -q "receiving state" "$work/client.err" && break
    sleep 0.2
done
sleep 3 # the first frames drawn in calm
"$build/client/gale-ctl" --url "ws://127.0.0.1:$port" --token-file "$work/token" wind --speed "$speed"
status=0
for _ in $(seq 600); do
    kill -0 "$client_pid" 2>/dev/null || break
    sleep 0.2
done
if kill -0 "$client_pid" 2>/dev/null; then
    echo "live-fall: no fall within 120 s of the dial" >&2
    status=1
else
    wait "$client_pid" || status=$?
    client_pid=""
fi
grep -E "fall (caught|shot)" "$work/client.err" || { echo "live-fall: no fall caught" >&2; status=1; }
exit "$status"
