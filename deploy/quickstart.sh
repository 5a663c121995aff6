#!/usr/bin/env bash
# Installs what is missing, builds, and runs the most complete thing gale does today on
# its embedded default: bakes the default species (report + mode-shape figure), starts
# gale-server on the embedded town-block scene, renders it with a headless gale-client,
# puts a short gale-load run against it, and stops the server with SIGTERM.
# Everything it writes goes to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/build.sh release
mkdir -p out
port="${GALE_PORT:-7780}"

echo "== gale-bake: the default species (oak), 32 modes"
./build/server/gale-bake --species configs/species/oak.json --modes 32 \
    --out out/oak.gasset --report out/oak-report.json --modes-png out/oak-modes.png

echo "== gale-server: embedded town-block scene on 127.0.0.1:${port}"
./build/server/gale-server --port "$port" --iface 127.0.0.1 --cache out/cache \
    >out/server.log 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true' EXIT
for _ in $(seq 1 600); do
    if grep -q "listening on port" out/server.log 2>/dev/null; then
        break
    fi
    if ! kill -0 "$server" 2>/dev/null; then
        cat out/server.log >&2
        exit 1
    fi
    sleep 0.1
done
grep -v "overran" out/server.log || true

echo "== gale-client: headless frame of the live scene -> out/gale-frame.png"
./build/client/gale-client --url "ws://127.0.0.1:${port}" --headless --frames 90 \
    --screenshot out/gale-frame.png

echo "== gale-load: 50 load clients for 10 s"
./build/client/gale-load --url "ws://127.0.0.1:${port}" --clients 50 --seconds 10 --json \
    | tee out/load.json

echo "== stopping the server (SIGTERM)"
kill -TERM "$server"
wait "$server" || true
trap - EXIT
tail -n 3 out/server.log
echo "gale: wrote out/oak.gasset, out/oak-report.json, out/oak-modes.png, out/gale-frame.png, out/load.json"
