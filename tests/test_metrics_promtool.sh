#!/bin/sh
# /metrics of the real gale-server passes `promtool check metrics` (Prometheus's own
# linter: base units, _total counters, histogram families), and carries the tick-time
# histogram, the recent ticks' summary, the tick's phases and gale_build_info (server/SERVER.md "Serving");
# the server's process keeps its name when it runs itself again.
# Usage: test_metrics_promtool.sh GALE_SERVER PROMTOOL SOURCE_DIR (run in the build tree)
set -eu
server="$1"; promtool="$2"; src="$3"
cat >promtool_scene.json <<JSON
{"name": "promtool", "species": [{"name": "palm", "file": "$src/configs/species/palm.json", "modes": 8}],
 "forest": [{"species": "palm", "count": 4, "area_min": [-20, -20], "area_max": [20, 20], "min_spacing_m": 3}],
 "wind": {"solver": false, "u10_ms": 12}}
JSON
# without OMP_WAIT_POLICY the server runs itself again (srv_main.c omp_wait_passive): the
# same process, which keeps its name
env -u OMP_WAIT_POLICY "$server" --config promtool_scene.json --port 0 --cache promtool_cache >promtool_server.out 2>promtool_server.log &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true' EXIT
port=""
i=0
while [ -z "$port" ] && [ $i -lt 900 ]; do
    port="$(sed -n 's/^gale-server: listening on port \([0-9]*\)$/\1/p' promtool_server.out)"
    kill -0 $pid 2>/dev/null || { cat promtool_server.log; exit 1; }
    sleep 0.1
    i=$((i + 1))
done
[ -n "$port" ] || { echo "server did not start"; exit 1; }
sleep 0.5
comm="$(cat /proc/$pid/comm)"
[ "$comm" = "gale-server" ] || { echo "the server's process is named '$comm', not gale-server"; exit 1; }
curl -sf "http://127.0.0.1:$port/metrics" >promtool_metrics.txt
"$promtool" check metrics <promtool_metrics.txt
grep -q '^# TYPE gale_tick_seconds histogram$' promtool_metrics.txt
grep -q '^gale_tick_seconds_bucket{le="+Inf"} [1-9]' promtool_metrics.txt
grep -q '^# TYPE gale_tick_recent_seconds summary$' promtool_metrics.txt
grep -q '^gale_tick_recent_seconds{quantile="0.99"} [0-9.]*$' promtool_metrics.txt
grep -q '^gale_tick_recent_seconds_count [1-9]' promtool_metrics.txt
# the tick's phases, publishing among them, each with time in it
for phase in sample modal leaves publish; do
    grep -q "^gale_tick_phase_seconds_total{phase=\"$phase\"} [0-9.]*[1-9]" promtool_metrics.txt ||
        { echo "no time in phase $phase"; exit 1; }
done
grep -q '^gale_tick_off_cpu_seconds_total [0-9.]*$' promtool_metrics.txt
grep -q '^gale_build_info{version="[0-9.]*",protocol="1"} 1$' promtool_metrics.txt
echo "promtool: /metrics clean ($(grep -c '^gale_' promtool_metrics.txt) samples)"
