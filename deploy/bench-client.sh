#!/usr/bin/env bash
# The client's CPU per display frame from socket bytes to the GL upload: starts gale-server
# on a loopback port with a scene (default configs/scenes/default.json), runs
# `gale-bench-client client --url` against it under Xvfb (a hidden GL window for the
# upload) and prints its JSON, which carries the load average.
set -euo pipefail
usage() {
    cat <<'USAGE'
usage: deploy/bench-client.sh [--scene FILE.json] [--frames N]
  --scene FILE  scene the server runs (default configs/scenes/default.json)
  --frames N    display frames measured at 60 Hz (default 600)
  --help        this text
USAGE
}
root="$(cd "$(dirname "$0")/.." && pwd)"
scene="$root/configs/scenes/default.json"
frames=600
while [ $# -gt 0 ]; do
    case "$1" in
        --help|-h) usage; exit 0 ;;
        --scene) scene="$2"; shift 2 ;;
        --frames) frames="$2"; shift 2 ;;
        *) echo "bench-client.sh: unknown argument $1" >&2; usage >&2; exit 2 ;;
    esac
done
bin="$root/build"
dir="$(mktemp -d "${TMPDIR:-/tmp}/gale-bench-client.XXXXXX")"
"$bin/server/gale-server" --config "$scene" --port 0 --iface 127.0.0.1 --cache "$dir/cache" \
    >"$dir/server.log" 2>&1 &
srv=$!
trap 'kill "$srv" 2>/dev/null; wait "$srv" 2>/dev/null; rm -rf "$dir"' EXIT
port=""
for _ in $(seq 1 600); do
    port="$(grep -o 'listening on port [0-9]*' "$dir/server.log" | grep -o '[0-9]*$' || true)"
    [ -n "$port" ] && break
    sleep 0.2
done
[ -n "$port" ] || { tail -n 20 "$dir/server.log" >&2; echo "bench-client.sh: no server" >&2; exit 1; }
xvfb-run -a -s "-screen 0 640x480x24" \
    "$bin/client/gale-bench-client" client --url "ws://127.0.0.1:$port" --frames "$frames"
