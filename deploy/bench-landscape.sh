#!/usr/bin/env bash
# Viewers of the 2 km landscape connecting at once (server/SERVER.md "The welcome"):
# gale-server with configs/scenes/landscape-2km.json (100,000 trees) runs B seconds with no
# client (its overruns on this machine alone), then N `gale-load --views --per-client`
# viewers connect together, each with a frustum view of its own (street, roof and aerial in
# turn, lod_m 120), take their welcomes for W seconds, and are measured for S seconds.
# /metrics is read at each phase's edges: overruns and ticks (alone, while the welcomes go
# out, measured), the tick's p99 of the last minute, hello timeouts (4009) and refused
# connections over the whole run, view encode time. Each client's figures come from
# gale-load: its welcome's first byte and its end after the hello, the bytes a second it
# received after its welcome, its latency p50/p99 (server timestamp to decode), its close
# code (0: none). gale-load decodes the welcome's scene part once and compares the other
# clients' bytes with it, so its own parsing does not take the server's cores. The load
# average (/proc/loadavg) at the start and the end says how busy the machine was. Prints
# one JSON object.
# Usage: deploy/bench-landscape.sh [clients 20] [seconds 60] [welcome seconds 20]
#                                  [alone seconds 20]
set -euo pipefail
cd "$(dirname "$0")/.."
clients="${1:-20}"
seconds="${2:-60}"
warm="${3:-20}"
alone="${4:-20}"
# gale-load's service threads: a thread busy with a welcome reads none of its other
# connections meanwhile, so the clients are spread over as many threads as it allows
threads="$(( clients < 16 ? clients : 16 ))"
build="${GALE_BUILD:-build}"
server="$build/server/gale-server"
load="$build/client/gale-load"
if [ ! -x "$server" ] || [ ! -x "$load" ]; then
    echo "bench-landscape: build first: $server and $load are needed" >&2
    exit 2
fi
loadavg() { awk '{printf "[%s, %s, %s]", $1, $2, $3}' /proc/loadavg; }
load_start="$(loadavg)"
mkdir -p out
log="out/bench-landscape-server.log"
"$server" --config configs/scenes/landscape-2km.json --port 0 --iface 127.0.0.1 \
    --cache out/cache >out/bench-landscape-server.out 2>"$log" &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true' EXIT
port=""
for _ in $(seq 1 3000); do
    port="$(sed -n 's/^gale-server: listening on port \([0-9]*\)$/\1/p' out/bench-landscape-server.out)"
    [ -n "$port" ] && break
    kill -0 "$pid" 2>/dev/null || { echo "bench-landscape: server exited:" >&2; cat "$log" >&2; exit 1; }
    sleep 0.1
done
[ -n "$port" ] || { echo "bench-landscape: server did not start" >&2; exit 1; }
welcome="$(sed -n 's/.*welcome \([0-9]*\) bytes, built in \([0-9.]*\) ms$/{"bytes": \1, "build_ms": \2}/p' "$log")"
page() { curl -s "http://127.0.0.1:$port/metrics"; }
metric() { awk -v k="$1" '$1 == k {print $2}' "$2"; }
sleep 2 # the first ticks fault in the scene's arrays
page >out/bench-landscape-a0.txt
sleep "$alone"
page >out/bench-landscape-a1.txt
"$load" --url "ws://127.0.0.1:$port" --clients "$clients" --seconds "$((warm + seconds + 2))" \
    --role viewer --views 900 --per-client --threads "$threads" --json >out/bench-landscape.json &
lpid=$!
sleep "$warm"
page >out/bench-landscape-m0.txt
sleep "$seconds"
page >out/bench-landscape-m1.txt
wait "$lpid" || true
vm="$(awk '/^VmRSS:/ {r=$2} END {printf "%s", r}' "/proc/$pid/status")"
kill -TERM "$pid"
wait "$pid" || true
trap - EXIT
load_end="$(loadavg)"
d() { awk -v a="$(metric "$1" "$2")" -v b="$(metric "$1" "$3")" 'BEGIN {printf "%.0f", b - a}'; }
a0=out/bench-landscape-a0.txt a1=out/bench-landscape-a1.txt
m0=out/bench-landscape-m0.txt m1=out/bench-landscape-m1.txt
p99="$(metric 'gale_tick_recent_seconds{quantile="0.99"}' "$m1")"
vsnaps="$(d gale_view_snapshots_total "$m0" "$m1")"
vsecs="$(awk -v a="$(metric gale_view_encode_seconds_total "$m0")" \
    -v b="$(metric gale_view_encode_seconds_total "$m1")" 'BEGIN {print b - a}')"
printf '{"bench": "landscape", "clients": %s, "load_threads": %s, "seconds": %s, "welcome": %s, "load_average": {"start": %s, "end": %s}, "server": {"alone": {"seconds": %s, "ticks": %s, "overruns": %s}, "welcomes": {"seconds": %s, "ticks": %s, "overruns": %s}, "measured": {"ticks": %s, "overruns": %s, "tick_p99_ms": %.2f, "view_snapshots": %s, "view_encode_us_each": %.1f}, "hello_timeouts": %s, "refused": %s, "rss_kb": %s}, "load": %s}\n' \
    "$clients" "$threads" "$seconds" "${welcome:-null}" "$load_start" "$load_end" \
    "$alone" "$(d gale_ticks_total "$a0" "$a1")" "$(d gale_tick_overruns_total "$a0" "$a1")" \
    "$warm" "$(d gale_ticks_total "$a1" "$m0")" "$(d gale_tick_overruns_total "$a1" "$m0")" \
    "$(d gale_ticks_total "$m0" "$m1")" "$(d gale_tick_overruns_total "$m0" "$m1")" \
    "$(awk -v x="$p99" 'BEGIN {print 1000 * x}')" "$vsnaps" \
    "$(awk -v s="$vsecs" -v n="$vsnaps" 'BEGIN {print n ? 1e6 * s / n : 0}')" \
    "$(d gale_hello_timeouts_total "$a1" "$m1")" "$(d gale_connections_refused_total "$a1" "$m1")" \
    "$vm" "$(tr -d '\n' <out/bench-landscape.json)"
