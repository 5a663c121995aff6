#!/usr/bin/env bash
# Configures and builds gale into build/ (RelWithDebInfo), or build-asan/ with
# `build.sh asan` (Debug + ASan/UBSan). Installs missing Debian packages first.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
kind="${1:-release}"
jobs="$(nproc)"
if [ "$kind" = asan ]; then
    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DGALE_SANITIZE=ON >/dev/null
    cmake --build build-asan -j "$jobs"
else
    cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
    cmake --build build -j "$jobs"
fi
