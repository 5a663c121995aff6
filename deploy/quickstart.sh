#!/usr/bin/env bash
# Installs what is missing, builds, and runs the most complete thing gale does today
# on its embedded default: bake the default species and print the bake report.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/build.sh release
mkdir -p out
./build/server/gale-bake --species configs/species/oak.json --modes 32 \
    --out out/oak.gasset --report out/oak-report.json --modes-png out/oak-modes.png
