#!/usr/bin/env bash
# Many views of the 2 km landscape (server/SERVER.md "Views and LOD"): gale-server with
# configs/scenes/landscape-2km.json, then `gale-load --views` with N clients, each asking
# for a view of its own (street, roof and aerial in turn, lod_m 120), on this machine.
# The clients come first and take their welcomes (100,000 instances each: seconds apiece
# on a busy machine) for W seconds; /metrics is then read at the start and the end of the
# S seconds measured: overruns,
# the tick's p99 of the last minute, view snapshots encoded, their mean encode time per
# snapshot of all views, snapshots the views missed; the load client's bytes a second per
# client by kind of view (over the whole run, the welcomes included). Prints one JSON line.
# Usage: deploy/bench-views.sh [clients 20] [seconds 60] [welcome seconds 120]
set -euo pipefail
cd "$(dirname "$0")/.."
clients="${1:-20}"
seconds="${2:-60}"
warm="${3:-120}"
build="${GALE_BUILD:-build}"
server="$build/server/gale-server"
load="$build/client/gale-load"
if [ ! -x "$server" ] || [ ! -x "$load" ]; then
    echo "bench-views: build first: $server and $load are needed" >&2
    exit 2
fi
mkdir -p out
log="out/bench-views-server.log"
"$server" --config configs/scenes/landscape-2km.json --port 0 --iface 127.0.0.1 \
    --cache out/cache >out/bench-views-server.out 2>"$log" &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true' EXIT
port=""
for _ in $(seq 1 3000); do
    port="$(sed -n 's/^gale-server: listening on port \([0-9]*\)$/\1/p' out/bench-views-server.out)"
    [ -n "$port" ] && break
    kill -0 "$pid" 2>/dev/null || { echo "bench-views: server exited:" >&2; cat "$log" >&2; exit 1; }
    sleep 0.1
done
[ -n "$port" ] || { echo "bench-views: server did not start" >&2; exit 1; }
page() { curl -s "http://127.0.0.1:$port/metrics"; }
metric() { awk -v k="$1" '$1 == k {print $2}' "$2"; }
"$load" --url "ws://127.0.0.1:$port" --clients "$clients" --seconds "$((warm + seconds + 5))" \
    --role viewer --views 900 --json >out/bench-views.json &
lpid=$!
sleep "$warm"
page >out/bench-views-m0.txt
sleep "$seconds"
page >out/bench-views-m1.txt
wait "$lpid" || true
vm="$(awk '/^VmRSS:/ {r=$2} /^VmSize:/ {s=$2} END {printf "{\"rss_kb\": %s, \"size_kb\": %s}", r, s}' \
    "/proc/$pid/status")"
kill -TERM "$pid"
wait "$pid" || true
trap - EXIT
d() { awk -v a="$(metric "$1" out/bench-views-m0.txt)" -v b="$(metric "$1" out/bench-views-m1.txt)" \
    'BEGIN {printf "%.6f", b - a}'; }
ticks="$(d gale_ticks_total)"
overruns="$(d gale_tick_overruns_total)"
vsnaps="$(d gale_view_snapshots_total)"
vsecs="$(d gale_view_encode_seconds_total)"
snaps="$(d gale_snapshots_total)"
publish="$(d 'gale_tick_phase_seconds_total{phase="publish"}')"
p99="$(metric 'gale_tick_recent_seconds{quantile="0.99"}' out/bench-views-m1.txt)"
printf '{"bench": "views", "clients": %s, "seconds": %s, "server": {"ticks": %.0f, "overruns": %.0f, "tick_p99_ms": %.2f, "publish_ms_per_snapshot": %.3f, "view_snapshots": %.0f, "view_encode_us_each": %.1f, "view_encode_ms_per_snapshot": %.2f, "view_missed": %.0f, "memory": %s}, "load": %s}\n' \
    "$clients" "$seconds" "$ticks" "$overruns" "$(awk -v x="$p99" 'BEGIN {print 1000 * x}')" \
    "$(awk -v p="$publish" -v n="$snaps" 'BEGIN {print n ? 1000 * p / n : 0}')" "$vsnaps" \
    "$(awk -v s="$vsecs" -v n="$vsnaps" 'BEGIN {print n ? 1e6 * s / n : 0}')" \
    "$(awk -v s="$vsecs" -v n="$snaps" 'BEGIN {print n ? 1000 * s / n : 0}')" \
    "$(d gale_view_snapshots_missed_total)" "$vm" \
    "$(tr -d '\n' <out/bench-views.json)"
