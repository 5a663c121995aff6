#!/usr/bin/env bash
# The 2 km landscape (100,000 trees) on a 2 × 2 wall of one browser tile and three
# gale-client tiles in one wall group (web/WEB.md "Wall tiles"): gale-server on
# configs/scenes/landscape-2km.json in calm with a kiosk token made for this run, the
# browser's tile c1r0 in headless chromium, a kiosk's camera over the town towards the
# north-east, the wall in calm and in a dialled Category 4 (OUT/wall-calm.png,
# OUT/wall-storm.png), the browser's c1r0 against gale-client's, and the far impostors'
# frame-to-frame motion in calm and in a dialled Category 3 in both clients. Prints one JSON
# object (tests/web/wall_landscape.mjs says what each figure is). Takes 3-4 minutes on two
# cores at load 2-5, longer on a busier machine.
# Usage: deploy/wall-landscape.sh [OUT (default out/wall-landscape)] [WxH per tile (640x360)]
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then
    sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
fi
out="${1:-out/wall-landscape}"
size="${2:-640x360}"
build="${GALE_BUILD:-build}"
deps="${GALE_WEB_DEPS:-$build/tests/web}"
for b in server/gale-server client/gale-client client/gale-ctl; do
    if [ ! -x "$build/$b" ]; then
        echo "wall-landscape: build first (deploy/build.sh); needs $build/$b" >&2
        exit 2
    fi
done
if [ ! -d "$deps/node_modules/playwright-core" ]; then
    echo "wall-landscape: needs playwright-core in $deps (ctest --test-dir $build -R web_npm_ci)" >&2
    exit 2
fi
mkdir -p "$out"
rm -rf "$out"/profile-*
# a kiosk token for this run only (the file stays under OUT, readable by its owner alone)
( umask 077 && od -An -N16 -tx1 /dev/urandom | tr -d ' \n' >"$out/token" && echo >>"$out/token" )
GALE_WEB_DEPS="$(cd "$deps" && pwd)" exec node tests/web/wall_landscape.mjs \
    "$build/server/gale-server" "$build/client/gale-client" "$build/client/gale-ctl" \
    "$out" "$out/token" "$size"
