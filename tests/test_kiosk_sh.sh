#!/bin/sh
# deploy/kiosk.sh without a display or cage: its loop restarts a client that exits, passes
# the kiosk options and the token file's first line, stops on a refused token (exit 4)
# without a restart, and without a desktop runs itself inside the compositor (a stand-in
# that only sets WAYLAND_DISPLAY and runs what follows "--").
# Usage: test_kiosk_sh.sh SOURCE_DIR (run in the build tree; writes under kiosk_sh/)
set -eu
kiosk="$1/deploy/kiosk.sh"
d="$PWD/kiosk_sh"
rm -rf "$d"
mkdir -p "$d"
printf 'sekrit\nignored\n' >"$d/token"
# the stand-in client: one line per run with its arguments, then the status in $d/status
cat >"$d/client" <<EOF
#!/bin/sh
echo "run \$*" >>"$d/runs"
exit \$(cat "$d/status")
EOF
cat >"$d/cage" <<EOF
#!/bin/sh
echo "cage" >>"$d/runs"
while [ "\$1" != -- ]; do shift; done
shift
WAYLAND_DISPLAY=wayland-test exec "\$@"
EOF
chmod +x "$d/client" "$d/cage"
fail() { echo "test_kiosk_sh: $*" >&2; cat "$d/runs" >&2 2>/dev/null || true; exit 1; }

# a client that keeps crashing: started, then restarted 3 times
echo 1 >"$d/status"
st=0
env -u DISPLAY -u WAYLAND_DISPLAY sh -c '"$@"' sh "$kiosk" --no-cage --url ws://127.0.0.1:9 \
    --token-file "$d/token" --backoff 0 --max-restarts 3 --client "$d/client" -- --camera street \
    2>"$d/log1" || st=$?
[ "$st" = 1 ] || fail "crashing client: exit $st, expected its status 1"
[ "$(grep -c '^run ' "$d/runs")" = 4 ] || fail "crashing client: expected 4 runs"
grep -qxF "run --url ws://127.0.0.1:9 --role kiosk --token-file $(readlink -f "$d/token") --fullscreen --camera street" \
    "$d/runs" || fail "client arguments"
! grep -q sekrit "$d/runs" || fail "the token itself on the client's command line"
[ "$(grep -c 'restart' "$d/log1")" = 3 ] || fail "expected 3 restart messages"

# a refused token: one run, exit 4, no restart
rm -f "$d/runs"
echo 4 >"$d/status"
st=0
env -u DISPLAY -u WAYLAND_DISPLAY sh -c '"$@"' sh "$kiosk" --no-cage --url ws://127.0.0.1:9 \
    --token-file "$d/token" --backoff 0 --max-restarts 3 --client "$d/client" 2>"$d/log2" || st=$?
[ "$st" = 4 ] || fail "refused token: exit $st, expected 4"
[ "$(grep -c '^run ' "$d/runs")" = 1 ] || fail "refused token: restarted"
grep -q 'not restarting' "$d/log2" || fail "refused token: no message"

# no desktop: the loop runs inside the compositor, once (it ends on the refused token)
rm -f "$d/runs"
st=0
env -u DISPLAY -u WAYLAND_DISPLAY sh -c '"$@"' sh "$kiosk" --url ws://127.0.0.1:9 \
    --token-file "$d/token" --backoff 0 --client "$d/client" --cage "$d/cage" 2>"$d/log3" || st=$?
[ "$st" = 4 ] || fail "under cage: exit $st, expected 4"
[ "$(head -n 1 "$d/runs")" = cage ] || fail "under cage: the compositor did not start first"
[ "$(grep -c '^cage' "$d/runs")" = 1 ] || fail "under cage: the compositor restarted"
[ "$(grep -c '^run ' "$d/runs")" = 1 ] || fail "under cage: expected one client run"

# under cage, a crashing client restarts inside the same compositor
rm -f "$d/runs"
echo 1 >"$d/status"
st=0
env -u DISPLAY -u WAYLAND_DISPLAY sh -c '"$@"' sh "$kiosk" --url ws://127.0.0.1:9 \
    --token-file "$d/token" --backoff 0 --max-restarts 2 --client "$d/client" --cage "$d/cage" \
    2>"$d/log4" || st=$?
[ "$st" = 1 ] || fail "under cage, crashing: exit $st, expected 1"
[ "$(grep -c '^cage' "$d/runs")" = 1 ] || fail "under cage, crashing: compositor restarted"
[ "$(grep -c '^run ' "$d/runs")" = 3 ] || fail "under cage, crashing: expected 3 runs"

# no desktop and no compositor: a clear message, exit 2
st=0
env -u DISPLAY -u WAYLAND_DISPLAY sh -c '"$@"' sh "$kiosk" --url ws://127.0.0.1:9 \
    --token-file "$d/token" --client "$d/client" --cage "$d/no-such-cage" 2>"$d/log5" || st=$?
[ "$st" = 2 ] || fail "no compositor: exit $st, expected 2"
grep -q 'apt-get install cage' "$d/log5" || fail "no compositor: message"
echo "test_kiosk_sh: ok"
