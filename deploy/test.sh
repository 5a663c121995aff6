#!/usr/bin/env bash
# Installs what is missing, builds twice (RelWithDebInfo, then Debug + ASan/UBSan) and
# runs the whole test suite on both, under a virtual X server for the render tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/build.sh release
bash deploy/build.sh asan
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
run_ctest() {
    xvfb-run -a -s "-screen 0 1280x1024x24" ctest --test-dir "$1" --output-on-failure -j 2
}
echo "== tests: RelWithDebInfo =="
run_ctest build
echo "== tests: Debug + ASan/UBSan =="
run_ctest build-asan
echo "== fuzz: every decoder, bounded time, ASan+UBSan (libFuzzer)"
bash deploy/fuzz.sh "${GALE_FUZZ_SECONDS:-15}"
echo "gale: all tests passed (release and sanitizer builds, fuzzing)"
