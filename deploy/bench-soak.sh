#!/usr/bin/env bash
# Soak benchmark (not a test; server/SERVER.md "Connections"): gale-server on its default
# scene for SECONDS (default 600) on loopback with 50 well-behaved gale-load clients beside
# hostile traffic from a python3 helper: connect/hello/disconnect churn at ~50 connections
# in flight, 20 stuck readers (hello, then never read; reconnected when culled) and one
# abusive client (ping floods, silent upgrades, reconnecting). Prints the server's RSS and
# descriptor count every 30 s, then one JSON line: the good clients' report (p99, gaps,
# disconnects), first/last RSS and fds, and whether the goals held (RSS and fds within
# ±5 % of the first sample after warm-up, p99 <= 50 ms, 0 gaps).
# Usage: deploy/bench-soak.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
build="${GALE_BUILD:-build}"
server="$build/server/gale-server"
load="$build/client/gale-load"
if [ ! -x "$server" ] || [ ! -x "$load" ] || ! command -v python3 >/dev/null; then
    echo "bench-soak: build first (deploy/build.sh); needs $server, $load and python3" >&2
    exit 2
fi
mkdir -p out
log="out/bench-soak-server.log"
# the gusty wind throughout: the default scene's playlist would bring Andrew after 2 min
"$server" --port 0 --iface 127.0.0.1 --cache out/cache --scenario configs/scenarios/gusty.json \
    >out/bench-soak-server.out 2>"$log" &
pid=$!
hpid=""
trap 'kill -TERM $pid 2>/dev/null || true; [ -n "$hpid" ] && kill $hpid 2>/dev/null || true' EXIT
port=""
for _ in $(seq 1 600); do
    port="$(sed -n 's/^gale-server: listening on port \([0-9]*\)$/\1/p' out/bench-soak-server.out)"
    [ -n "$port" ] && break
    kill -0 "$pid" 2>/dev/null || { echo "bench-soak: server exited:" >&2; cat "$log" >&2; exit 1; }
    sleep 0.1
done
[ -n "$port" ] || { echo "bench-soak: server did not start" >&2; exit 1; }
rss() { awk '/^VmRSS:/ {print $2}' "/proc/$pid/status"; }
fds() { ls "/proc/$pid/fd" | wc -l; }

python3 - "$port" "$seconds" <<'EOF' &
import random, socket, sys, threading, time
port, seconds = int(sys.argv[1]), float(sys.argv[2])
end = time.time() + seconds
UPGRADE = (b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
           b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
           b"Sec-WebSocket-Protocol: gale\r\n\r\n")
def frame(text):
    b, m = text.encode(), b"\x12\x34\x56\x78"
    n = len(b)
    head = bytes([0x81, 0x80 | n]) if n < 126 else bytes([0x81, 0xfe, n >> 8, n & 255])
    return head + m + bytes(x ^ m[i % 4] for i, x in enumerate(b))
HELLO = frame('{"type": "hello", "protocol": 1, "role": "viewer"}')
def conn(rcvbuf=0):
    s = socket.socket()
    if rcvbuf:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
    s.settimeout(3)
    s.connect(("127.0.0.1", port))
    s.sendall(UPGRADE)
    return s
def churn():  # connect, hello, read a little, leave
    while time.time() < end:
        try:
            s = conn()
            s.sendall(HELLO)
            t = time.time() + random.uniform(0.2, 2.0)
            while time.time() < t:
                s.recv(65536)
            s.close()
        except OSError:
            time.sleep(0.1)
PONG = bytes([0x8a, 0x80]) + b"\x12\x34\x56\x78"  # unsolicited pong: ignored by the server
def stuck():  # hello, then never read; the server culls it, so come back
    while time.time() < end:
        try:
            s = conn(4096)
            s.sendall(HELLO)
            while time.time() < end:
                time.sleep(1)
                s.sendall(PONG)  # fails (reset) once the server has closed the socket
        except OSError:
            time.sleep(0.5)
def abuse():  # ping floods and silent upgrades
    ping = frame('{"type": "ping", "id": 1, "client_us": 1}')
    while time.time() < end:
        try:
            s = conn()
            if random.random() < 0.5:
                s.sendall(HELLO + ping * 200)
            time.sleep(random.uniform(0.1, 6.0))
            s.close()
        except OSError:
            time.sleep(0.1)
threads = [threading.Thread(target=churn) for _ in range(50)]
threads += [threading.Thread(target=stuck) for _ in range(20)]
threads += [threading.Thread(target=abuse)]
for t in threads:
    t.daemon = True
    t.start()
for t in threads:
    t.join()
EOF
hpid=$!
"$load" --url "ws://127.0.0.1:$port" --clients 50 --seconds "$seconds" --json >out/bench-soak.json &
lpid=$!
samples=()
# every sample is taken while the load runs (the last one 30 s or less before its end)
for ((t = 30; t < seconds; t += 30)); do
    sleep 30
    r="$(rss)" f="$(fds)"
    samples+=("$r $f")
    echo "bench-soak: ${t} s: RSS ${r} kB, ${f} descriptors" >&2
done
wait "$lpid" || true
wait "$hpid" || true
kill -TERM "$pid"
status=0
wait "$pid" || status=$?
trap - EXIT
# the first sample is the warm-up (pool, caches); the goals compare the rest with the second
first="${samples[1]:-${samples[0]:-0 0}}"
last="${samples[-1]:-0 0}"
python3 - "$first" "$last" "$status" "${samples[@]:1}" <<'EOF'
import json, sys
first, last, status = sys.argv[1].split(), sys.argv[2].split(), int(sys.argv[3])
after = [tuple(int(x) for x in s.split()) for s in sys.argv[4:]] or [(0, 0)]
rep = json.load(open("out/bench-soak.json"))
r0, f0, r1, f1 = int(first[0]), int(first[1]), int(last[0]), int(last[1])
flat = lambda a, b: a > 0 and abs(b - a) <= 0.05 * a
p99 = rep["latency_ms"]["p99"]
gaps = rep["sequence_gaps"]
print(json.dumps({"bench": "soak", "good_clients": rep, "server": {
    "rss_kb": {"first": r0, "last": r1, "min": min(a[0] for a in after),
               "max": max(a[0] for a in after)},
    "fds": {"first": f0, "last": f1, "min": min(a[1] for a in after),
            "max": max(a[1] for a in after)},
    "exit_status": status},
    "goals": {"rss_flat": flat(r0, r1), "fds_flat": flat(f0, f1), "p99_le_50ms": p99 <= 50,
              "no_gaps": gaps == 0}}))
EOF
