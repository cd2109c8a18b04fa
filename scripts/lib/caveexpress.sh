# SPDX-License-Identifier: MIT
# shellcheck shell=bash
# scripts/lib/caveexpress.sh: Debian's caveexpress binary package started on a map under Xvfb, and quadphase's
# validation reports read from a log; shared by scripts/real-game.sh and scripts/deb-check.sh. Source it after
# lib/build.sh:
#
#   source "$(dirname "${BASH_SOURCE[0]}")/lib/caveexpress.sh"
#
#   qp_validation_counts LOG      "<mismatch lines> <UpdatePairs checked, or - when LOG has no summary>"
#   qp_xvfb_start LOG             Xvfb on the first free display >= :99 (sets QP_DISPLAY, QP_XVFB_PID); 1 if it did
#                                 not come up within 5 s
#   qp_game_start LOG HOME MAP [VAR=VALUE...]
#                                 /usr/games/caveexpress -map MAP on QP_DISPLAY (sets QP_GAME_PID), output in LOG,
#                                 HOME as given, no sound, Mesa's software GL, LD_LIBRARY_PATH unset unless a
#                                 VAR=VALUE sets it; waits for the server's "start the map" and returns 1 when no map
#                                 started within 60 s. The game's own -map command line loads the map, opens its
#                                 server and connects its client: a level runs.
#   qp_game_maps_line             the game's /proc/PID/maps line for libbox2d.so ("" when none)
#   qp_game_stop                  SIGTERM, SDL's quit event: the game shuts its map down (deleting the b2World, which
#                                 prints validation's summary) and exits; killed after 10 s (sets QP_GAME_STATUS)
#   qp_x_cleanup                  kills the game and Xvfb if they still run (for an EXIT trap)
readonly QP_GAME=/usr/games/caveexpress
QP_DISPLAY="" QP_XVFB_PID="" QP_GAME_PID="" QP_GAME_STATUS=""

qp_validation_counts() {
    local mismatches checked
    mismatches=$(grep -c '^quadphase: validation mismatch' "$1" || true)
    checked=$(sed -n 's/^quadphase: validation: \([0-9]*\) UpdatePairs checked.*/\1/p' "$1" |
              awk '{ n += $1; seen = 1 } END { print seen ? n : "-" }')
    echo "$mismatches $checked"
}

qp_xvfb_start() {
    local display=99
    while [[ -e /tmp/.X11-unix/X$display || -e /tmp/.X$display-lock ]]; do display=$((display + 1)); done
    Xvfb ":$display" -screen 0 1024x768x24 -nolisten tcp >"$1" 2>&1 &
    QP_XVFB_PID=$!
    QP_DISPLAY=:$display
    for _ in $(seq 50); do
        [[ -e /tmp/.X11-unix/X$display ]] && return 0
        sleep 0.1
    done
    return 1
}

qp_game_start() {
    local log=$1 home=$2 map=$3
    env -u LD_LIBRARY_PATH DISPLAY="$QP_DISPLAY" HOME="$home" SDL_AUDIODRIVER=dummy LIBGL_ALWAYS_SOFTWARE=1 \
        "${@:4}" "$QP_GAME" -map "$map" >"$log" 2>&1 &
    QP_GAME_PID=$!
    # The level runs from the server's "start the map" (a few seconds of start-up under Mesa's software GL).
    for _ in $(seq 600); do
        grep -q "start the map" "$log" 2>/dev/null && return 0
        kill -0 "$QP_GAME_PID" 2>/dev/null || break
        sleep 0.1
    done
    grep -q "start the map" "$log"
}

qp_game_maps_line() {
    grep -m1 'libbox2d\.so' "/proc/$QP_GAME_PID/maps" 2>/dev/null || true
}

qp_game_stop() {
    kill -TERM "$QP_GAME_PID" 2>/dev/null || true
    for _ in $(seq 100); do
        kill -0 "$QP_GAME_PID" 2>/dev/null || break
        sleep 0.1
    done
    kill -KILL "$QP_GAME_PID" 2>/dev/null || true # still running after 10 s: status 137
    QP_GAME_STATUS=0
    { wait "$QP_GAME_PID"; } 2>/dev/null || QP_GAME_STATUS=$? # the status says it; no "Aborted" line from bash
    QP_GAME_PID=""
}

qp_x_cleanup() {
    if [[ -n "$QP_GAME_PID" ]]; then kill -KILL "$QP_GAME_PID" 2>/dev/null || true; fi
    if [[ -n "$QP_XVFB_PID" ]]; then kill "$QP_XVFB_PID" 2>/dev/null || true; fi
    QP_GAME_PID="" QP_XVFB_PID=""
}
