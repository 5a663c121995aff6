#!/usr/bin/env bash
# Runs one exhibit kiosk (gale-client --role kiosk --fullscreen) and restarts it whenever it
# exits, so a visitor never sees a crash or a desktop. On a desktop ($DISPLAY or
# $WAYLAND_DISPLAY set) the kiosk opens fullscreen there. Without one (a bare console or a
# systemd unit on a seat, deploy/gale-kiosk.service) the script runs itself under cage, a
# Wayland compositor that shows one application fullscreen and nothing else: the restart
# loop runs inside cage, so between two runs of the client the screen stays cage's black,
# never a console or a desktop.
# GLFW: Debian's libglfw3 is built for X11 only (libglfw3-wayland is the other build), so
# under cage the client draws through Xwayland, which cage's wlroots starts on demand when
# the xwayland package is installed; cage then sets $DISPLAY for the client. With
# libglfw3-wayland installed the client draws to cage directly; the script is the same.
# A refused token (gale-client exit 4) or bad options (2) are the operator's to fix: the
# script stops with the client's message instead of retrying.
# The client reads the token from the file itself (gale-client --token-file), so it stays
# out of the process list, unit files and shell history.
set -euo pipefail

usage() {
    cat <<'EOF'
usage: deploy/kiosk.sh --url ws://HOST:PORT --token-file FILE [--backoff S] [--max-backoff S]
                       [--max-restarts N] [--no-cage] [--client CMD] [--cage CMD]
                       [-- gale-client options...]
  --url U           the gale-server (required)
  --token-file F    file holding the server's kiosk token (gale-server --kiosk-token-file);
                    its first line is used
  --backoff S       wait before the first restart (default 1); doubles on each quick
                    exit up to --max-backoff (default 30), back to S after a run of 60 s
  --max-restarts N  stop after N restarts (default: never; for tests)
  --no-cage         run the client here even without a desktop
  --client CMD      the kiosk program (default $GALE_BUILD/client/gale-client, else
                    gale-client on $PATH); tests give a stand-in
  --cage CMD        the compositor (default cage)
  -- ...            passed to gale-client as they are (e.g. --camera street --attract 120)
Without $DISPLAY or $WAYLAND_DISPLAY the kiosk runs under cage (Debian: apt-get install
cage xwayland; Xwayland because Debian's GLFW is X11-only).
Exit status: 2 bad arguments or cage missing; 4 the server refused the token; with
--max-restarts, the client's last status; else it runs until stopped (SIGTERM, Ctrl-C).
EOF
}

self="$(cd "$(dirname "$0")" && pwd)/$(basename "$0")"
orig_args=("$@")
url=""
token_file=""
backoff_s=1
max_backoff_s=30
max_restarts=-1
no_cage=0
in_cage=0
client_cmd=""
cage_cmd="cage"
extra=()
while [ $# -gt 0 ]; do
    case "$1" in
    --help | -h) usage; exit 0 ;;
    --url) url="${2:?--url: expected ws://HOST:PORT}"; shift 2 ;;
    --token-file) token_file="${2:?--token-file: expected a file}"; shift 2 ;;
    --backoff) backoff_s="${2:?--backoff: expected seconds}"; shift 2 ;;
    --max-backoff) max_backoff_s="${2:?--max-backoff: expected seconds}"; shift 2 ;;
    --max-restarts) max_restarts="${2:?--max-restarts: expected N}"; shift 2 ;;
    --no-cage) no_cage=1; shift ;;
    --in-cage) in_cage=1; shift ;; # the copy of this script that cage runs
    --client) client_cmd="${2:?--client: expected a program}"; shift 2 ;;
    --cage) cage_cmd="${2:?--cage: expected a program}"; shift 2 ;;
    --) shift; extra+=("$@"); break ;;
    *) echo "kiosk.sh: unknown option \"$1\" (see --help)" >&2; exit 2 ;;
    esac
done
int_re='^[0-9]+$'
[ -n "$url" ] || { echo "kiosk.sh: --url ws://HOST:PORT is required (see --help)" >&2; exit 2; }
[ -n "$token_file" ] || { echo "kiosk.sh: --token-file FILE is required (see --help)" >&2; exit 2; }
[ -r "$token_file" ] || { echo "kiosk.sh: --token-file $token_file: cannot read" >&2; exit 2; }
for v in "$backoff_s" "$max_backoff_s"; do
    [[ "$v" =~ $int_re ]] || { echo "kiosk.sh: backoff \"$v\": expected whole seconds" >&2; exit 2; }
done
[[ "$max_restarts" =~ $int_re ]] || [ "$max_restarts" = -1 ] ||
    { echo "kiosk.sh: --max-restarts \"$max_restarts\": expected N" >&2; exit 2; }
[ -n "$(head -n 1 "$token_file" | tr -d '\r\n')" ] ||
    { echo "kiosk.sh: --token-file $token_file: first line is empty" >&2; exit 2; }
token_file="$(readlink -f "$token_file")" # the client may start elsewhere (under cage)
if [ -z "$client_cmd" ]; then
    client_cmd="${GALE_BUILD:-build}/client/gale-client"
    [ -x "$client_cmd" ] || client_cmd="$(command -v gale-client || true)"
    [ -n "$client_cmd" ] || { echo "kiosk.sh: gale-client: not built (deploy/build.sh) nor on \$PATH" >&2; exit 2; }
fi

# No desktop: the same script again, inside cage, which ends when the script does. A stop
# file tells this side that the inner loop stopped on purpose (token refused, bad options),
# since cage need not pass its client's exit status on.
if [ "$in_cage" = 0 ] && [ "$no_cage" = 0 ] && [ -z "${DISPLAY:-}" ] && [ -z "${WAYLAND_DISPLAY:-}" ]; then
    command -v "$cage_cmd" >/dev/null ||
        { echo "kiosk.sh: no desktop and no $cage_cmd (apt-get install cage xwayland, or --no-cage)" >&2; exit 2; }
    stop_file="$(mktemp "${TMPDIR:-/tmp}/gale-kiosk.XXXXXX")"
    trap 'rm -f "$stop_file"' EXIT
    trap 'exit 0' INT TERM
    delay_s="$backoff_s"
    while :; do
        : >"$stop_file"
        t0="$(date +%s)"
        GALE_KIOSK_STOP_FILE="$stop_file" "$cage_cmd" -- "$self" --in-cage "${orig_args[@]}" || true
        if [ -s "$stop_file" ]; then
            exit "$(cat "$stop_file")"
        fi
        [ $(( $(date +%s) - t0 )) -ge 60 ] && delay_s="$backoff_s"
        echo "kiosk.sh: $cage_cmd exited; restarting in ${delay_s} s" >&2
        sleep "$delay_s"
        delay_s=$(( delay_s * 2 > max_backoff_s ? max_backoff_s : delay_s * 2 ))
    done
fi

# The restart loop: the client in the foreground, its status read on each exit.
child=0
stop() {
    [ "$child" -gt 0 ] && kill -TERM "$child" 2>/dev/null
    exit 0
}
trap stop INT TERM
restarts=0
delay_s="$backoff_s"
while :; do
    t0="$(date +%s)"
    status=0
    "$client_cmd" --url "$url" --role kiosk --token-file "$token_file" --fullscreen "${extra[@]}" &
    child=$!
    wait "$child" || status=$?
    child=0
    if [ "$status" = 2 ] || [ "$status" = 4 ]; then
        echo "kiosk.sh: gale-client exited $status (see its message above); not restarting" >&2
        [ -n "${GALE_KIOSK_STOP_FILE:-}" ] && echo "$status" >"$GALE_KIOSK_STOP_FILE"
        exit "$status"
    fi
    if [ "$max_restarts" != -1 ] && [ "$restarts" -ge "$max_restarts" ]; then
        [ -n "${GALE_KIOSK_STOP_FILE:-}" ] && echo "$status" >"$GALE_KIOSK_STOP_FILE"
        exit "$status"
    fi
    [ $(( $(date +%s) - t0 )) -ge 60 ] && delay_s="$backoff_s"
    restarts=$((restarts + 1))
    echo "kiosk.sh: gale-client exited $status; restart $restarts in ${delay_s} s" >&2
    sleep "$delay_s"
    delay_s=$(( delay_s * 2 > max_backoff_s ? max_backoff_s : delay_s * 2 ))
done
