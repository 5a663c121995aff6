#!/usr/bin/env bash
# Mutation check: applies each one-line mutation of deploy/mutants.list to a scratch copy
# of the working tree, rebuilds it (one build directory, incremental per mutation), runs
# the test named for it and reports whether that test failed (killed) or passed
# (survived). Every listed mutation must be killed. Run by hand or nightly; not part of
# .ci/run (a full pass takes a long time on 2 cores).
set -euo pipefail

usage() {
    cat <<'EOF'
usage: deploy/mutants.sh [--list FILE] [--only N[,N...]] [--dir DIR] [--keep]
  --list FILE   mutations, one a line: file ||| text ||| replacement ||| ctest regex
                (default deploy/mutants.list; the text's first occurrence is replaced)
  --only N,...  run only these entries (1-based, in list order)
  --dir DIR     scratch directory (default: a new one under ${TMPDIR:-/tmp}); an existing
                one's build is reused, so a second run rebuilds only what changed
  --keep        leave the scratch directory in place
  --help        this text
Exit status: 0 every mutation killed, 1 a mutation survived or could not be applied,
2 bad arguments or an unmutated test failing.
EOF
}

root="$(cd "$(dirname "$0")/.." && pwd)"
list="$root/deploy/mutants.list"
only=""
dir=""
keep=0
while [ $# -gt 0 ]; do
    case "$1" in
        --help|-h) usage; exit 0 ;;
        --list) list="$2"; shift 2 ;;
        --only) only=",$2,"; shift 2 ;;
        --dir) dir="$2"; shift 2 ;;
        --keep) keep=1; shift ;;
        *) echo "mutants.sh: unknown argument $1" >&2; usage >&2; exit 2 ;;
    esac
done
[ -r "$list" ] || { echo "mutants.sh: $list: cannot read" >&2; exit 2; }
if [ -z "$dir" ]; then
    dir="$(mktemp -d "${TMPDIR:-/tmp}/gale-mutants.XXXXXX")"
fi
if [ "$keep" = 0 ]; then
    trap 'rm -rf "$dir"' EXIT
fi
src="$dir/src"
bld="$dir/build"
mkdir -p "$src"

# The working tree as it is (tracked and untracked, not ignored), copied only where it
# differs so a reused build stays incremental.
(cd "$root" && git ls-files -co --exclude-standard -z) | while IFS= read -r -d '' f; do
    if [ -f "$root/$f" ] && ! cmp -s "$root/$f" "$src/$f"; then
        mkdir -p "$src/$(dirname "$f")"
        cp "$root/$f" "$src/$f"
    fi
done

jobs="${GALE_MUTANTS_JOBS:-2}"
echo "== mutants: scratch $dir, load average $(cut -d' ' -f1-3 /proc/loadavg)"
cmake -S "$src" -B "$bld" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
nice cmake --build "$bld" -j "$jobs" >"$dir/build.log" 2>&1 || {
    tail -n 30 "$dir/build.log" >&2
    echo "mutants.sh: the unmutated tree does not build" >&2
    exit 2
}

run_tests() { # regex -> status of ctest
    xvfb-run -a -s "-screen 0 1280x1024x24" \
        ctest --test-dir "$bld" -R "^($1)\$" --timeout 900 >"$dir/test.log" 2>&1
}

# Parse the list: file, text, replacement, tests.
entries=()
while IFS= read -r line || [ -n "$line" ]; do
    case "$line" in ''|'#'*) continue ;; esac
    entries+=("$line")
done <"$list"

field() { # line n -> the n-th ' ||| '-separated field, trimmed of the separator's spaces
    awk -v n="$2" 'BEGIN { FS = " \\|\\|\\| " } { print $n }' <<<"$1"
}

# Every named test passes on the unmutated tree, or a kill means nothing.
all=""
for e in "${entries[@]}"; do
    t="$(field "$e" 4)"
    all="${all:+$all|}$t"
done
if ! run_tests "$all"; then
    tail -n 30 "$dir/test.log" >&2
    echo "mutants.sh: a named test fails on the unmutated tree" >&2
    exit 2
fi

printf '%-3s %-9s %-11s %-22s %-28s %s\n' "#" result by test file mutation
survived=0
n=0
for e in "${entries[@]}"; do
    n=$((n + 1))
    if [ -n "$only" ] && [[ "$only" != *",$n,"* ]]; then
        continue
    fi
    file="$(field "$e" 1)"
    text="$(field "$e" 2)"
    repl="$(field "$e" 3)"
    tests="$(field "$e" 4)"
    target="$src/$file"
    cp "$target" "$dir/orig"
    if ! MUT_TEXT="$text" MUT_REPL="$repl" python3 - "$target" <<'PY'
import os, sys
p = sys.argv[1]
s = open(p, encoding="utf-8").read()
t, r = os.environ["MUT_TEXT"], os.environ["MUT_REPL"]
if t not in s:
    sys.exit(1)
open(p, "w", encoding="utf-8").write(s.replace(t, r, 1))
PY
    then
        result="NOT-FOUND"
        by="-"
        survived=$((survived + 1))
    elif ! nice cmake --build "$bld" -j "$jobs" >"$dir/build.log" 2>&1; then
        result="killed"
        by="build"
    elif run_tests "$tests"; then
        result="SURVIVED"
        by="-"
        survived=$((survived + 1))
    else
        result="killed"
        by="test"
    fi
    # restored with a new modification time, so the next build recompiles it
    cp "$dir/orig" "$target"
    short="$(printf '%s -> %s' "$text" "$repl" | tr -s ' ' | cut -c1-110)"
    printf '%-3s %-9s %-11s %-22s %-28s %s\n' "$n" "$result" "$by" "$tests" "$file" "$short"
done
nice cmake --build "$bld" -j "$jobs" >"$dir/build.log" 2>&1 || true
echo "== mutants: $n listed, $survived survived or not applied; load average" \
    "$(cut -d' ' -f1-3 /proc/loadavg)"
[ "$survived" = 0 ]
