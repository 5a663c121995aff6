#!/usr/bin/env bash
# Relay benchmark (server/SERVER.md "Relays"): gale-server --nats, nats-server, two
# gale-relays and gale-load with CLIENTS split across the relays for SECONDS, then the same
# load on gale-server alone (no NATS), on this machine's loopback. Prints one JSON object:
# per run, every process's CPU seconds over the load window and per delivered
# client-second, and each load's delivered state frames, latency p50/p99 and skipped
# snapshots; with the load average. With VIEWS_HALF_M every client sends a view of its
# own (gale-load --views: street, roof and aerial views, eyes within VIEWS_HALF_M of the
# origin), which the relays select and encode themselves and the server alone for its own
# clients; the view snapshots each process encoded are reported (/metrics).
# Usage: deploy/bench-relay.sh [CLIENTS] [SECONDS] [VIEWS_HALF_M]
set -euo pipefail
cd "$(dirname "$0")/.."
clients="${1:-300}"
seconds="${2:-20}"
views_half_m="${3:-}"
views=()
[ -n "$views_half_m" ] && views=(--views "$views_half_m")
build="${GALE_BUILD:-build}"
server="$build/server/gale-server"
relay="$build/server/gale-relay"
load="$build/client/gale-load"
nats="$(command -v nats-server || echo /usr/sbin/nats-server)"
for x in "$server" "$relay" "$load" "$nats"; do
    [ -x "$x" ] || { echo "bench-relay: $x is needed (deploy/build.sh)" >&2; exit 2; }
done
out="out/bench-relay"
mkdir -p "$out"
pids=()
cleanup() { for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
hz="$(getconf CLK_TCK)"
cpu() { awk '{print $14 + $15}' "/proc/$1/stat"; }
# waits for "<prefix> N" on the file's first line; prints N
port_of() {
    for _ in $(seq 1 900); do
        p="$(sed -n "s/^$2 \([0-9]*\)$/\1/p" "$1")"
        [ -n "$p" ] && { echo "$p"; return 0; }
        sleep 0.1
    done
    echo "bench-relay: no port in $1" >&2
    return 1
}
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
# the view and slow-reader counters of the /metrics page on port $1, as JSON
metrics() {
    python3 - "$1" <<'PY'
import json, sys, urllib.request
names = ["gale_view_snapshots_total", "gale_view_encode_seconds_total",
         "gale_view_snapshots_missed_total", "gale_relay_view_snapshots_total",
         "gale_relay_view_encode_seconds_total", "gale_relay_snapshots_unsent_total",
         "gale_snapshots_unsent_total", "gale_decimations_total", "gale_frame_waits_total",
         "gale_frames_dropped_total"]
try:
    body = urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/metrics", timeout=5).read().decode()
except Exception:
    body = ""
rows = dict(l.split()[:2] for l in body.splitlines() if len(l.split()) >= 2 and l[0] != "#")
print(json.dumps({n[5:]: float(rows[n]) for n in names if n in rows}))
PY
}
echo "bench-relay: $(uptime)" >&2
# --- run 1: server + NATS + 2 relays --------------------------------------------------
np="$(free_port)"
"$nats" -a 127.0.0.1 -p "$np" >"$out/nats.log" 2>&1 &
npid=$!; pids+=("$npid")
sleep 0.5
"$server" --port 0 --cache out/cache --nats "nats://127.0.0.1:$np" >"$out/server.out" 2>"$out/server.log" &
spid=$!; pids+=("$spid")
sport="$(port_of "$out/server.out" "gale-server: listening on port")"
rpids=(); rports=()
for k in 1 2; do
    "$relay" --nats "nats://127.0.0.1:$np" --port 0 >"$out/relay$k.out" 2>"$out/relay$k.log" &
    rpids+=($!); pids+=($!)
    rports+=("$(port_of "$out/relay$k.out" "gale-relay: listening on port")")
done
sleep 2
half=$(( clients / 2 ))
c_s0="$(cpu "$spid")"; c_n0="$(cpu "$npid")"; c_a0="$(cpu "${rpids[0]}")"; c_b0="$(cpu "${rpids[1]}")"
"$load" --url "ws://127.0.0.1:${rports[0]}" --clients "$half" --seconds "$seconds" "${views[@]}" --json >"$out/load1.json" &
l1=$!
"$load" --url "ws://127.0.0.1:${rports[1]}" --clients "$(( clients - half ))" --seconds "$seconds" "${views[@]}" --json >"$out/load2.json" &
l2=$!
wait "$l1" "$l2"
c_s1="$(cpu "$spid")"; c_n1="$(cpu "$npid")"; c_a1="$(cpu "${rpids[0]}")"; c_b1="$(cpu "${rpids[1]}")"
load_relay="$(uptime | sed 's/.*load average: //')"
metrics "$sport" >"$out/metrics_server.json"
metrics "${rports[0]}" >"$out/metrics_relay1.json"
metrics "${rports[1]}" >"$out/metrics_relay2.json"
cleanup; wait 2>/dev/null || true; pids=()

# --- run 2: the same load on gale-server alone ----------------------------------------
"$server" --port 0 --cache out/cache >"$out/alone.out" 2>"$out/alone.log" &
spid=$!; pids+=("$spid")
aport="$(port_of "$out/alone.out" "gale-server: listening on port")"
sleep 2
c_x0="$(cpu "$spid")"
"$load" --url "ws://127.0.0.1:$aport" --clients "$clients" --seconds "$seconds" "${views[@]}" --json >"$out/load_alone.json"
c_x1="$(cpu "$spid")"
load_alone="$(uptime | sed 's/.*load average: //')"
metrics "$aport" >"$out/metrics_alone.json"
cleanup; wait 2>/dev/null || true; pids=()
trap - EXIT

python3 - "$hz" "$clients" "$seconds" "$out" "$c_s0" "$c_s1" "$c_n0" "$c_n1" "$c_a0" "$c_a1" \
    "$c_b0" "$c_b1" "$c_x0" "$c_x1" "$load_relay" "$load_alone" "$views_half_m" <<'PY'
import json, sys
hz, clients, secs, out = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
t = [int(x) for x in sys.argv[5:15]]
cpu = lambda a, b: round((b - a) / hz, 2)
def load(name):
    j = json.load(open(f"{out}/{name}"))
    return {"connected": j["connected"], "state_frames": j["state_frames"],
            "client_seconds": round(j["state_frames"] / 30.0, 1), "p50_ms": j["latency_ms"]["p50"],
            "p99_ms": j["latency_ms"]["p99"], "skipped_snapshots": j["skipped_snapshots"],
            "decode_errors": j["decode_errors"], "disconnects": j["disconnects"]}
l1, l2, la = load("load1.json"), load("load2.json"), load("load_alone.json")
cs = l1["client_seconds"] + l2["client_seconds"]
relay = {"cpu_s": {"gale-server": cpu(t[0], t[1]), "nats-server": cpu(t[2], t[3]),
                   "relay1": cpu(t[4], t[5]), "relay2": cpu(t[6], t[7])},
         "loads": [l1, l2], "client_seconds": cs}
# server and broker per client-second of all relayed clients, each relay per its own
per = {"gale-server": cs, "nats-server": cs, "relay1": l1["client_seconds"],
       "relay2": l2["client_seconds"]}
relay["us_per_client_s"] = {k: round(1e6 * v / per[k], 1) if per[k] else None
                            for k, v in relay["cpu_s"].items()}
relay["load_average"] = sys.argv[15]
views = sys.argv[17]
relay["metrics"] = {k: json.load(open(f"{out}/metrics_{f}.json"))
                    for k, f in (("gale-server", "server"), ("relay1", "relay1"),
                                 ("relay2", "relay2"))}
alone = {"cpu_s": {"gale-server": cpu(t[8], t[9])}, "loads": [la],
         "client_seconds": la["client_seconds"], "load_average": sys.argv[16],
         "metrics": {"gale-server": json.load(open(f"{out}/metrics_alone.json"))}}
alone["us_per_client_s"] = {"gale-server": round(1e6 * alone["cpu_s"]["gale-server"] /
                                                 la["client_seconds"], 1) if la["client_seconds"] else None}
p99 = lambda r: max(l["p99_ms"] for l in r["loads"])
print(json.dumps({"bench": "relay", "clients": clients, "seconds": secs,
                  "views_half_m": float(views) if views else None,
                  "relays": relay, "server_alone": alone,
                  "p99_relays_over_alone": round(p99(relay) / p99(alone), 2) if p99(alone) else None}))
PY
