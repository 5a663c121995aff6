#!/usr/bin/env bash
# Installs the Debian 12 packages gale builds, tests and runs with. Idempotent:
# installs only what is missing, so a second run costs a dpkg query.
set -euo pipefail

pkgs=(
    build-essential cmake pkg-config
    libcjson-dev libwebsockets-dev
    libopenblas-dev liblapacke-dev libarpack2-dev
    libglfw3-dev libepoxy-dev libegl-dev libgl-dev libcglm-dev libstb-dev fonts-dejavu-core
    libasound2-dev
    xvfb xauth libgl1-mesa-dri libegl-mesa0 libglx-mesa0
    clang libclang-rt-14-dev curl openssl
    valgrind
    nats-server libnats-dev
    prometheus lintian dpkg-dev
    chromium
)
# The browser tests (tests/web) run under Node with npm; a machine that has both from
# elsewhere keeps them (Debian's npm would conflict with another nodejs package).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    pkgs+=(nodejs npm)
fi

missing=()
for p in "${pkgs[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
[ "${#missing[@]}" -eq 0 ] && exit 0

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
    SUDO="sudo"
fi
echo "gale: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
