#!/usr/bin/env bash
# gale live in one command: installs what is missing and builds (progress lines here, the
# compiler's output in out/build.log), starts gale-server on the embedded town-block scene
# with a fresh kiosk token, then
# - with a display: opens the kiosk window at street level (close it to stop);
# - headless: dials a breeze, a gale, a tropical storm, Category 2 and Category 4 with
#   gale-ctl and renders each at street level (one frame each: out/street-*.png, with
#   the HUD text a visitor reads in out/street-*.txt);
# and ends by printing the commands to try next. Everything it writes goes to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p out
port="${GALE_PORT:-7780}"
url="ws://127.0.0.1:${port}"

step() { printf '== %s\n' "$*"; }

step "building gale (release) … (compiler output: out/build.log)"
if ! bash deploy/build.sh release >out/build.log 2>&1; then
    tail -n 30 out/build.log >&2
    echo "quickstart: the build failed; the whole log is out/build.log" >&2
    exit 1
fi
step "built: build/server/gale-server, build/client/gale-client, build/client/gale-ctl"

token_file=out/kiosk-token
if [ ! -s "$token_file" ]; then
    # readable by this user alone: the token lets its holder dial the wind
    (umask 077; head -c 12 /dev/urandom | od -An -tx1 | tr -d ' \n' >"$token_file"
     echo >>"$token_file")
fi

step "gale-server: the embedded town block on 127.0.0.1:${port} (species baked on first run)"
./build/server/gale-server --port "$port" --iface 127.0.0.1 --cache out/cache \
    --kiosk-token-file "$token_file" >out/server.log 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true' EXIT
for _ in $(seq 1 3000); do
    if grep -q "listening on port" out/server.log 2>/dev/null; then
        break
    fi
    if ! kill -0 "$server" 2>/dev/null; then
        cat out/server.log >&2
        exit 1
    fi
    sleep 0.1
done
grep -E "species|scenario|listening on 127" out/server.log || true

ctl() { ./build/client/gale-ctl --url "$url" --token-file "$token_file" "$@" >/dev/null; }

if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && [ -z "${GALE_HEADLESS:-}" ]; then
    step "gale-client: the kiosk at street level (drag to look, F11 fullscreen, Esc quits)"
    ./build/client/gale-client --url "$url" --role kiosk --token-file "$token_file" \
        --camera street --size 1280x720 2>out/client.log || true
else
    step "headless: breeze → Category 4 at street level, one frame each"
    n=0
    for speed in 4.5 17 30 45 60; do
        n=$((n + 1))
        ctl wind --speed "$speed" --dir 200
        # the dial moves the wind at 4 m/s per second (scenario dial_rate_ms2)
        sleep "$(awk -v s="$speed" 'BEGIN { printf "%d", s / 4 + 3 }')"
        png="out/street-${n}.png"
        ./build/client/gale-client --url "$url" --headless --frames 1 --size 1280x720 \
            --camera street --screenshot "$png" 2>>out/client.log | sed 's/^hud: //' \
            >"out/street-${n}.txt"
        printf '   %s: %s (%s)\n' "$png" "$(sed -n 2p "out/street-${n}.txt")" \
            "$(sed -n 1p "out/street-${n}.txt")"
    done
    ctl release
fi

step "stopping the server"
kill -TERM "$server"
wait "$server" || true
trap - EXIT
cat <<EOF

gale: next, try
  ./build/server/gale-server --port $port --kiosk-token-file $token_file --scenario configs/scenarios/andrew1992.json --start-min -40 --replay-speed 10
  ./build/client/gale-client --url $url --role kiosk --token-file $token_file --camera street
  ./build/client/gale-ctl --url $url --token-file $token_file wind --speed 50 --dir 90
  ./build/client/gale-ctl --url $url --token-file $token_file replay --at landfall --speed 10
  ./build/client/gale-ctl --url $url --token-file $token_file release
  ./build/client/gale-client --url $url --headless --frames 1 --camera aerial --screenshot out/aerial.png
and with the server running, open http://127.0.0.1:$port/ in a browser (/kiosk for the kiosk)
EOF
