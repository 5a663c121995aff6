#!/usr/bin/env bash
# Builds every tests/fuzz/fuzz_*.c as a libFuzzer program (CMake option GALE_FUZZ: clang,
# -fsanitize=fuzzer with ASan + UBSan, into build-fuzz/) and runs each for a bounded time
# from its seed corpus tests/fuzz/corpus/<name>/.
# Then, unless NAMEs were given or node is missing, the browser's decoders (web/wire.js,
# web/asset.js) against protocol/'s built the same way (gale-web-decode-dump, ASan + UBSan)
# for SECONDS: tests/web/fuzz_web_decoders.mjs, a disagreement's input in build-fuzz/web/.
# Usage: deploy/fuzz.sh [SECONDS per target, default 20] [NAME ...]
# Exits non-zero when any target crashes, leaks or trips a sanitizer; the crashing input
# is left in build-fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-20}"
shift || true
case "$secs" in
    ''|*[!0-9]*) echo "fuzz.sh: SECONDS must be a whole number, got '$secs'" >&2; exit 2 ;;
esac
command -v clang >/dev/null || { echo "fuzz.sh: clang not found (apt-get install clang)" >&2; exit 2; }

cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=Debug -DGALE_FUZZ=ON \
    -DCMAKE_C_FLAGS="-O1 -g" >/dev/null
mkdir -p build-fuzz/artifacts
if [ "$#" -gt 0 ]; then
    names=("$@")
else
    names=()
    for src in tests/fuzz/fuzz_*.c; do
        n="$(basename "$src" .c)"
        names+=("${n#fuzz_}")
    done
fi
fail=0
for name in "${names[@]}"; do
    src="tests/fuzz/fuzz_${name}.c"
    [ -f "$src" ] || { echo "fuzz.sh: no $src" >&2; fail=1; continue; }
    bin="build-fuzz/tests/fuzz/fuzz_${name}"
    cmake --build build-fuzz -j 2 --target "fuzz_${name}" >"build-fuzz/build_${name}.log" 2>&1 || {
        echo "fuzz ${name}: FAILED to build (log build-fuzz/build_${name}.log)" >&2
        tail -20 "build-fuzz/build_${name}.log" >&2
        fail=1
        continue
    }
    work="$(mktemp -d)"
    seeds="tests/fuzz/corpus/${name}"
    dirs=("$work")
    [ -d "$seeds" ] && dirs+=("$seeds")
    echo "== fuzz ${name}: ${secs} s from $(find "$seeds" -type f 2>/dev/null | wc -l) seeds"
    if ! "$bin" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
            -print_final_stats=1 -artifact_prefix="build-fuzz/artifacts/${name}-" \
            "${dirs[@]}" 2>"build-fuzz/fuzz_${name}.log"; then
        echo "fuzz ${name}: FAILED (log build-fuzz/fuzz_${name}.log):" >&2
        tail -40 "build-fuzz/fuzz_${name}.log" >&2
        fail=1
    else
        grep -E 'stat::number_of_executed_units|cov:' "build-fuzz/fuzz_${name}.log" | tail -2 || true
    fi
    rm -rf "$work"
done
if [ "$#" -eq 0 ] && command -v node >/dev/null; then
    echo "== fuzz web decoders: ${secs} s"
    if ! cmake --build build-fuzz -j 2 --target gale-web-decode-dump >build-fuzz/build_web.log 2>&1; then
        echo "fuzz web: FAILED to build (log build-fuzz/build_web.log)" >&2
        tail -20 build-fuzz/build_web.log >&2
        fail=1
    elif ! node tests/web/fuzz_web_decoders.mjs build-fuzz/tests/web/gale-web-decode-dump build-fuzz/web \
            --seconds "$secs" --seed "$(date +%s)"; then
        echo "fuzz web: FAILED (input in build-fuzz/web/)" >&2
        fail=1
    fi
fi
exit "$fail"
