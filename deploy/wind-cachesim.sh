#!/usr/bin/env bash
# The wind step's memory traffic measured, beside its byte model: gale-bench wind runs
# under valgrind's callgrind with a simulated last-level cache (2 MiB by default, smaller
# than the grid's working set, as a DRAM-sized grid is to a real L3), twice with
# different step counts; the difference of the last-level misses (reads and write
# allocations, 64-byte lines: STREAM's convention, write-backs not counted) over the
# extra steps, per cell, by phase (inclusive costs of wind_advect, wind_mg_solve and
# wind_project; forces, borders and divergence are the rest of wind_step), is printed as JSON
# with the model's figures.
set -euo pipefail

usage() {
    cat <<'USAGE'
usage: deploy/wind-cachesim.sh [--grid 128x128x16] [--cell-m 2] [--subgrid-profile]
                              [--ll-kib 2048] [--bench PATH]
  --grid G     wind grid (default 128x128x16: 16 MB of working set)
  --cell-m H   cell edge in m (default 2; the landscape scene: --grid 250x250x2 --cell-m 8)
  --subgrid-profile  the grid samples with the subgrid profile (as that scene does)
  --ll-kib K   simulated last-level cache (default 2048)
  --bench P    gale-bench to run (default build/server/gale-bench)
  --help       this text
USAGE
}

root="$(cd "$(dirname "$0")/.." && pwd)"
grid=128x128x16
cell_m=2
extra=()
ll_kib=2048
bench="$root/build/server/gale-bench"
while [ $# -gt 0 ]; do
    case "$1" in
        --help|-h) usage; exit 0 ;;
        --grid) grid="$2"; shift 2 ;;
        --cell-m) cell_m="$2"; shift 2 ;;
        --subgrid-profile) extra+=(--subgrid-profile); shift ;;
        --ll-kib) ll_kib="$2"; shift 2 ;;
        --bench) bench="$2"; shift 2 ;;
        *) echo "wind-cachesim.sh: unknown argument $1" >&2; usage >&2; exit 2 ;;
    esac
done
command -v valgrind >/dev/null || { echo "wind-cachesim.sh: valgrind missing (deploy/install-deps.sh)" >&2; exit 2; }
[ -x "$bench" ] || { echo "wind-cachesim.sh: $bench: not built" >&2; exit 2; }
dir="$(mktemp -d "${TMPDIR:-/tmp}/gale-cachesim.XXXXXX")"
trap 'rm -rf "$dir"' EXIT

# warm-up (10 steps) and set-up are in both runs and cancel in the difference
short=2
long=6
for s in $short $long; do
    valgrind --tool=callgrind --cache-sim=yes --LL=$((ll_kib * 1024)),16,64 \
        --callgrind-out-file="$dir/cg.$s" \
        "$bench" wind --grid "$grid" --cell-m "$cell_m" "${extra[@]}" --steps "$s" --threads 1 \
        --no-triad >"$dir/bench.$s" \
        2>"$dir/vg.$s"
    callgrind_annotate --inclusive=yes --show=DLmr,DLmw --threshold=100 "$dir/cg.$s" \
        >"$dir/ann.$s"
done
python3 - "$dir" "$grid" "$short" "$long" "$ll_kib" <<'PY'
import json, re, sys
d, grid, short, long_, ll = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
nx, ny, nz = map(int, grid.split("x"))
cells = nx * ny * nz

def phases(path):
    inc = {}
    pat = re.compile(r"^\s*([\d,]+|\.)\s*(?:\([^)]*\))?\s+([\d,]+|\.)\s*(?:\([^)]*\))?\s+"
                     r"(\S+):(\S+)")
    for line in open(path):
        m = pat.match(line)
        if not m:
            continue
        n = lambda g: 0 if g == "." else int(g.replace(",", ""))
        fn = m.group(4)
        inc[fn] = max(inc.get(fn, 0), n(m.group(1)) + n(m.group(2)))
    step = inc.get("wind_step", 0)
    adv = inc.get("wind_advect", 0) + inc.get("wind_fill_ghosts", 0)
    solve = inc.get("wind_mg_solve", 0)
    proj = max(inc.get("wind_project", 0), inc.get("wind_project._omp_fn.0", 0))
    return {"advect": adv, "pressure_solve": solve, "projection": proj,
            "forces_bc_divergence": step - adv - solve - proj}

a, b = phases(f"{d}/ann.{short}"), phases(f"{d}/ann.{long_}")
steps = long_ - short
meas = {k: round((b[k] - a[k]) * 64.0 / steps / cells, 1) for k in a}
meas["total"] = round(sum(meas.values()), 1)
bench = json.loads(open(f"{d}/bench.{long_}").read())
model = bench["bytes_per_cell_model"]
with open("/proc/loadavg") as f:
    load = [float(x) for x in f.read().split()[:3]]
print(json.dumps({
    "grid": [nx, ny, nz], "cell_m": bench["inputs"]["cell_m"], "cells": cells, "ll_cache_kib": int(ll), "line_bytes": 64,
    "steps_differenced": steps, "iterations_mean": bench["iterations_mean"],
    "measured_bytes_per_cell_per_step": meas,
    "model_bytes_per_cell_per_step": {
        "advect": model["advect"], "pressure_solve": model["pressure_solve"],
        "projection": model["projection"], "forces_bc_divergence": model["forces_bc_divergence"],
        "total": model["total"]},
    "loadavg": load}))
PY
