#!/usr/bin/env bash
# Wall benchmark (not a test; protocol/PROTOCOL.md "Wall groups"): gale-server on the
# client-test scene and the four tiles of configs/walls/flat-2x2.json as headless
# gale-client processes on this machine for SECONDS (default 60, from the last tile's join)
# each run, once free-running
# and once in swap-lock mode, every tile writing --frame-log. From the frame logs, over the
# group frames every tile presented: tile-to-tile skew of the rendered server time (max -
# min per frame) and the spread of the swap instants (CLOCK_MONOTONIC, one machine), p50,
# p99 and max; frames each tile did not present between the first and last common frame;
# swap-lock budget timeouts. One JSON object per mode, with the load average before and
# after. Goals: skew p99 <= 1 ms (0 in swap-lock for frames all presented), swap
# spread p99 <= 2 ms in swap-lock.
# Usage: deploy/bench-wall.sh [SECONDS] [SIZE] [RATE]   (SIZE WxH per tile, default 320x180;
# RATE the group's frames a second, default 60)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
size="${2:-320x180}"
rate="${3:-60}"
build="${GALE_BUILD:-build}"
server="$build/server/gale-server"
client="$build/client/gale-client"
wall_file="configs/walls/flat-2x2.json"
if [ ! -x "$server" ] || [ ! -x "$client" ] || ! command -v python3 >/dev/null; then
    echo "bench-wall: build first (deploy/build.sh); needs $server, $client and python3" >&2
    exit 2
fi
out="out/bench-wall"
mkdir -p "$out"
"$server" --config tests/data/clientnet_scene.json --port 0 --iface 127.0.0.1 \
    --cache out/cache >"$out/server.out" 2>"$out/server.log" &
spid=$!
trap 'kill -TERM $spid 2>/dev/null || true' EXIT
port=""
for _ in $(seq 1 600); do
    port="$(sed -n 's/^gale-server: listening on port \([0-9]*\)$/\1/p' "$out/server.out")"
    [ -n "$port" ] && break
    kill -0 "$spid" 2>/dev/null || { echo "bench-wall: server exited:" >&2; cat "$out/server.log" >&2; exit 1; }
    sleep 0.1
done
[ -n "$port" ] || { echo "bench-wall: server did not start" >&2; exit 1; }
tiles="$("$client" --wall "$wall_file" --list-tiles)"

run_mode() { # mode: free | swap-lock
    local mode="$1" extra=() pids=()
    [ "$mode" = swap-lock ] && extra=(--swap-lock)
    local load0
    load0="$(cut -d' ' -f1-3 /proc/loadavg)"
    for t in $tiles; do
        "$client" --url "ws://127.0.0.1:$port" --wall "$wall_file" --tile "$t" --headless \
            --size "$size" --rate "$rate" --frames 100000000 --wait 60 --cache out/cache-client \
            --frame-log "$out/$mode-$t.log" "${extra[@]}" 2>"$out/$mode-$t.err" &
        pids+=($!)
    done
    # every tile runs SECONDS after the last one joined (SIGTERM: they finish cleanly)
    for t in $tiles; do
        for _ in $(seq 1 600); do
            grep -q "joined at" "$out/$mode-$t.err" 2>/dev/null && break
            sleep 0.1
        done
    done
    sleep "$seconds"
    for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
    for p in "${pids[@]}"; do wait "$p" || true; done
    python3 - "$mode" "$load0" "$(cut -d' ' -f1-3 /proc/loadavg)" "$(nproc)" "$size" \
        "$seconds" "$out" "$rate" $tiles <<'EOF'
import json, re, sys
mode, load0, load1, cpus, size, seconds, out, rate = sys.argv[1:9]
tiles = sys.argv[9:]
logs, timeouts = {}, {}
for t in tiles:
    d = {}
    for line in open(f"{out}/{mode}-{t}.log"):
        mono, server, frame = (int(x) for x in line.split())
        d[frame] = (mono, server)
    logs[t] = d
    m = re.search(r"swap timeouts (\d+)", open(f"{out}/{mode}-{t}.err").read())
    timeouts[t] = int(m.group(1)) if m else None
common = set.intersection(*(set(d) for d in logs.values()))
lo, hi = (min(common), max(common)) if common else (0, -1)
def pct(v, p):
    v = sorted(v)
    return v[min(len(v) - 1, int(p / 100 * len(v)))] if v else None
skew = [max(logs[t][f][1] for t in tiles) - min(logs[t][f][1] for t in tiles) for f in common]
spread = [max(logs[t][f][0] for t in tiles) - min(logs[t][f][0] for t in tiles) for f in common]
missed = {t: sum(1 for f in range(lo, hi + 1) if f not in logs[t]) for t in tiles}
print(json.dumps({
    "bench": "wall", "mode": mode, "wall": "flat-2x2", "tiles": len(tiles), "tile_size": size,
    "seconds": float(seconds), "rate_hz": float(rate), "cpus": int(cpus),
    "loadavg_before": load0, "loadavg_after": load1,
    "frames_common": len(common), "frames_span": hi - lo + 1,
    "skew_us": {"p50": pct(skew, 50), "p99": pct(skew, 99), "max": max(skew, default=None)},
    "swap_spread_us": {"p50": pct(spread, 50), "p99": pct(spread, 99),
                       "max": max(spread, default=None)},
    "frames_missed_per_tile": missed,
    "swap_timeouts_per_tile": timeouts,
    "goals": {"skew_p99_le_1ms": (pct(skew, 99) or 0) <= 1000,
              "swap_spread_p99_le_2ms": mode != "swap-lock" or (pct(spread, 99) or 0) <= 2000},
}))
EOF
}
run_mode free
run_mode swap-lock
