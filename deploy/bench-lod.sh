#!/usr/bin/env bash
# Level-of-detail benchmark of gale-client (client/CLIENT.md "Budgets"): gale-server on the
# town block (the embedded scene) and on the 2 km landscape, and for each a headless
# gale-client at 1920x1080 from the street, roof and aerial cameras, following its view,
# in calm and with the wind dialled to STORM_MS; each run draws FRAMES frames after its
# first state. Per run: the last frame's draw calls, triangles, trees at each level, the
# frames' median culling and LOD time, the stream's bytes a second, the seconds to the
# frames and its screenshot (out/bench-lod/SCENE-CAMERA-WIND.png). Prints one JSON object
# with the load average and the renderer.
# Usage: deploy/bench-lod.sh [FRAMES] [STORM_MS] [SCENES...]   (SCENES: town landscape)
set -euo pipefail
cd "$(dirname "$0")/.."
frames="${1:-10}"
storm="${2:-60}"
shift $(($# > 2 ? 2 : $#))
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(town landscape)
build="${GALE_BUILD:-build}"
server="$build/server/gale-server"
client="$build/client/gale-client"
ctl="$build/client/gale-ctl"
for x in "$server" "$client" "$ctl"; do
    [ -x "$x" ] || { echo "bench-lod: $x is needed (deploy/build.sh)" >&2; exit 2; }
done
out="out/bench-lod"
mkdir -p "$out"
token="$out/kiosk-token"
(umask 077; head -c 12 /dev/urandom | od -An -tx1 | tr -d ' \n' >"$token"; echo >>"$token")
xvfb=()
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
    xvfb=(xvfb-run -a -s "-screen 0 1920x1080x24")
fi
srv=""
cleanup() { [ -n "$srv" ] && kill -TERM "$srv" 2>/dev/null || true; }
trap cleanup EXIT
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }

runs=()
for scene in "${scenes[@]}"; do
    case "$scene" in
    town) cfg=() ;;
    landscape) cfg=(--config configs/scenes/landscape-2km.json) ;;
    *) echo "bench-lod: unknown scene $scene (town, landscape)" >&2; exit 2 ;;
    esac
    port="$(free_port)"
    url="ws://127.0.0.1:$port"
    "$server" --port "$port" --iface 127.0.0.1 --cache out/cache --kiosk-token-file "$token" \
        "${cfg[@]}" >"$out/server-$scene.log" 2>&1 &
    srv=$!
    for _ in $(seq 1 6000); do
        grep -q "listening on port" "$out/server-$scene.log" 2>/dev/null && break
        kill -0 "$srv" 2>/dev/null || { cat "$out/server-$scene.log" >&2; exit 1; }
        sleep 0.1
    done
    for wind in calm storm; do
        if [ "$wind" = storm ]; then
            # a large scene's welcome can take a while on a loaded machine: a few tries
            for try in 1 2 3 4 5; do
                "$ctl" --url "$url" --token-file "$token" wind --speed "$storm" --dir 200 \
                    >/dev/null && break
                [ "$try" -lt 5 ] || { echo "bench-lod: gale-ctl failed 5 times" >&2; exit 1; }
                sleep 2
            done
            # the dial moves the wind at 4 m/s per second (scenario dial_rate_ms2)
            sleep "$(awk -v s="$storm" 'BEGIN { printf "%d", s / 4 + 3 }')"
        fi
        for cam in street roof aerial; do
            tag="$scene-$cam-$wind"
            t0="$(date +%s.%N)"
            "${xvfb[@]}" "$client" --url "$url" --headless --frames "$frames" --size 1920x1080 \
                --camera "$cam" --screenshot "$out/$tag.png" --wait 240 \
                >"$out/$tag.out" 2>"$out/$tag.err" || true
            t1="$(date +%s.%N)"
            line="$(grep '^render:' "$out/$tag.out" || true)"
            bps="$(sed -n 's/.*stream \([0-9.]*\) bytes\/s.*/\1/p' "$out/$tag.err" | tail -1)"
            val() {
                local v
                v="$(awk -v k="$1" '{ for (i = 2; i < NF; i++) if ($i == k) print $(i + 1) }' <<<"$line")"
                echo "${v:-null}"
            }
            runs+=("$(printf '{"scene":"%s","camera":"%s","wind":"%s","draw_calls":%s,"triangles":%s,"trees_full":%s,"trees_thin":%s,"impostors":%s,"culled":%s,"lod_scale":%s,"cull_ms_median":%s,"stream_bytes_s":%s,"seconds":%.1f,"png":"%s"}' \
                "$scene" "$cam" "$wind" "$(val draw_calls)" "$(val triangles)" "$(val trees_full)" \
                "$(val trees_thin)" "$(val impostors)" "$(val culled)" "$(val lod_scale)" \
                "$(val cull_ms_median)" "${bps:-0}" "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')" "$out/$tag.png")")
        done
    done
    kill -TERM "$srv"
    wait "$srv" 2>/dev/null || true
    srv=""
done
renderer="$(grep -ho 'renderer [^;,]*' "$out"/*.err 2>/dev/null | head -1 || true)"
printf '{"bench":"lod","frames":%s,"storm_ms":%s,"size":"1920x1080","loadavg":"%s","renderer":"%s","runs":[%s]}\n' \
    "$frames" "$storm" "$(cut -d' ' -f1-3 /proc/loadavg)" "${renderer:-?}" "$(IFS=,; echo "${runs[*]}")"
