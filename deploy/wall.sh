#!/usr/bin/env bash
# Starts every tile of a wall file (configs/walls/README.md) on this machine, one
# gale-client each, in windows or headless, all in the wall's group (protocol/PROTOCOL.md
# "Wall groups"); stops them all on Ctrl-C or SIGTERM. One tile per machine instead:
# deploy/gale-tile@.service.
set -euo pipefail

usage() {
    cat <<'EOF'
usage: deploy/wall.sh FILE [--url ws://HOST:PORT] [--headless] [--frames N] [--size WxH]
                      [--out DIR] [--swap-lock] [-- gale-client options...]
  FILE          the wall file
  --url U       the server (default ws://127.0.0.1:8080)
  --headless    offscreen tiles (tests, benchmarks); each stops after --frames
  --frames N    headless: frames per tile after state arrives (default 120)
  --size WxH    every tile's framebuffer (default: each tile's px from the file)
  --out DIR     headless: DIR/TILE.png, DIR/TILE.frames (frame log), DIR/TILE.log
                (default out/wall)
  --swap-lock   present in swap-lock (tiles wait for the group's "swap N")
  -- ...        passed to every gale-client as they are
Exit status: 0 when every tile exited 0, 1 when one did not, 2 on bad arguments.
Client binary: $GALE_BUILD/client/gale-client (GALE_BUILD default build).
EOF
}

[ "${1:-}" = --help ] || [ "${1:-}" = -h ] && { usage; exit 0; }
[ $# -ge 1 ] || { usage >&2; exit 2; }
file="$1"
shift
url="ws://127.0.0.1:8080"
headless=0
frames=120
size=""
outdir="out/wall"
extra=()
while [ $# -gt 0 ]; do
    case "$1" in
    --url) url="${2:?--url: expected ws://HOST:PORT}"; shift 2 ;;
    --headless) headless=1; shift ;;
    --frames) frames="${2:?--frames: expected N}"; shift 2 ;;
    --size) size="${2:?--size: expected WxH}"; shift 2 ;;
    --out) outdir="${2:?--out: expected a directory}"; shift 2 ;;
    --swap-lock) extra+=(--swap-lock); shift ;;
    --help | -h) usage; exit 0 ;;
    --) shift; extra+=("$@"); break ;;
    *) echo "wall.sh: unknown option \"$1\" (see --help)" >&2; exit 2 ;;
    esac
done
client="${GALE_BUILD:-build}/client/gale-client"
[ -x "$client" ] || { echo "wall.sh: $client: not built (deploy/build.sh)" >&2; exit 2; }
[ -r "$file" ] || { echo "wall.sh: $file: cannot read" >&2; exit 2; }
tiles="$("$client" --wall "$file" --list-tiles)" || exit 2
mkdir -p "$outdir"

pids=()
stop() {
    for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
}
trap stop INT TERM
for t in $tiles; do
    args=(--url "$url" --wall "$file" --tile "$t" --frame-log "$outdir/$t.frames")
    [ -n "$size" ] && args+=(--size "$size")
    if [ "$headless" = 1 ]; then
        args+=(--headless --frames "$frames" --screenshot "$outdir/$t.png")
    fi
    "$client" "${args[@]}" "${extra[@]}" 2>"$outdir/$t.log" &
    pids+=($!)
done
echo "wall.sh: $(echo "$tiles" | wc -w) tiles of $file on $url (logs in $outdir)" >&2
status=0
for p in "${pids[@]}"; do
    wait "$p" || status=1
done
exit "$status"
