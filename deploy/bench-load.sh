#!/usr/bin/env bash
# Load benchmark: gale-server on its default scene (60 Hz, 30 snapshots/s) and gale-load
# with 500 clients for 60 s on loopback. Prints one JSON object: the load report (p99
# latency, decode errors, disconnects), the server's RSS at start / middle / end, and its
# counters (ticks, overruns, frames dropped). Usage: deploy/bench-load.sh [CLIENTS] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
clients="${1:-500}"
seconds="${2:-60}"
build="${GALE_BUILD:-build}"
server="$build/server/gale-server"
load="$build/client/gale-load"
if [ ! -x "$server" ] || [ ! -x "$load" ]; then
    echo "bench-load: build first (deploy/build.sh): $server and $load are needed" >&2
    exit 2
fi
mkdir -p out
log="out/bench-load-server.log"
"$server" --port 0 --iface 127.0.0.1 --cache out/cache >out/bench-load-server.out 2>"$log" &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true' EXIT
port=""
for _ in $(seq 1 600); do
    port="$(sed -n 's/^gale-server: listening on port \([0-9]*\)$/\1/p' out/bench-load-server.out)"
    [ -n "$port" ] && break
    kill -0 "$pid" 2>/dev/null || { echo "bench-load: server exited:" >&2; cat "$log" >&2; exit 1; }
    sleep 0.1
done
[ -n "$port" ] || { echo "bench-load: server did not start" >&2; exit 1; }
rss() { awk '/^VmRSS:/ {print $2}' "/proc/$pid/status"; }
metric() { curl -s "http://127.0.0.1:$port/metrics" | awk -v k="$1" '$1 == k {print $2}'; }
sleep 2
rss_start="$(rss)"
"$load" --url "ws://127.0.0.1:$port" --clients "$clients" --seconds "$seconds" --json \
    >out/bench-load.json &
lpid=$!
sleep "$(( seconds / 2 ))"
rss_mid="$(rss)"
wait "$lpid" || true
rss_end="$(rss)"
ticks="$(metric gale_ticks_total)"
overruns="$(metric gale_tick_overruns_total)"
tmax="$(metric gale_tick_seconds_max)"
tsum="$(metric gale_tick_seconds_sum)"
dropped="$(metric gale_frames_dropped_total)"
laggards="$(metric gale_laggards_closed_total)"
kill -TERM "$pid"
status=0
wait "$pid" || status=$?
trap - EXIT
printf '{"bench": "load", "clients": %s, "seconds": %s, "load": %s, "server": {"rss_kb": {"start": %s, "middle": %s, "end": %s}, "ticks": %s, "overruns": %s, "tick_ms_mean": %s, "tick_ms_max": %s, "frames_dropped": %s, "laggards_closed": %s, "exit_status": %s}}\n' \
    "$clients" "$seconds" "$(tr -d '\n' <out/bench-load.json)" "$rss_start" "$rss_mid" "$rss_end" \
    "$ticks" "$overruns" "$(awk -v s="$tsum" -v n="$ticks" 'BEGIN {printf "%.3f", n ? 1000*s/n : 0}')" \
    "$(awk -v s="$tmax" 'BEGIN {printf "%.3f", 1000*s}')" "$dropped" "$laggards" "$status"
