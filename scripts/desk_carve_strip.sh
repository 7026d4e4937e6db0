#!/usr/bin/env bash
# scripts/desk_carve_strip.sh [OUT_PNG]: makes the README's film strip of a mouse carve at the desk again. A
# private Xvfb screen (1600x900) shows `tridex run` in a window (the default scene, mono, the mouse as the stylus);
# xdotool drives it with real X events: a groove dragged across the bunny's side (subtract, one radius deep), then
# key 3 and a painted band below it; Esc ends the session, whose --record recording `tridex replay --strip` draws
# as six pictures into OUT_PNG (default docs/images/desk_carve.png). The recording and the session's outputs stay
# in out/desk_carve/. Needs Xvfb and xdotool (scripts/install-deps.sh installs both) and a built tridex
# (build/release/app/tridex, or $TRIDEX). Exits non-zero, saying why, when a step fails.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
tridex="${TRIDEX:-$root/build/release/app/tridex}"
png="${1:-$root/docs/images/desk_carve.png}"
work="$root/out/desk_carve"
for tool in Xvfb xdotool; do
    command -v "$tool" > /dev/null || { echo "desk_carve_strip: $tool is not installed (scripts/install-deps.sh)" >&2; exit 1; }
done
[ -x "$tridex" ] || { echo "desk_carve_strip: no tridex at $tridex (make build)" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

display=":$((200 + $$ % 500))"
Xvfb "$display" -screen 0 1600x900x24 -nolisten tcp > "$work/xvfb.log" 2>&1 &
xvfb=$!
app=""
cleanup() {
    [ -n "$app" ] && kill "$app" 2> /dev/null || true
    kill "$xvfb" 2> /dev/null || true
}
trap cleanup EXIT
export DISPLAY="$display"
for _ in $(seq 50); do xdotool getmouselocation > /dev/null 2>&1 && break; sleep 0.1; done

"$tridex" run --display window --record "$work/desk_carve.trdx" --out "$work/session" --no-journal \
    > "$work/run.log" 2>&1 &
app=$!
win="$(timeout 120 xdotool search --sync --onlyvisible --name 'tridex run' | head -1)"
# The window opens at 80% of the screen (1280x720 at the top left): positions below are in its pixels.
sleep 3
drag() {  # drag X0 Y0 DX DY STEPS: the left button held along a line, a step every 40 ms
    local x="$1" y="$2" dx="$3" dy="$4" n="$5"
    xdotool mousemove --window "$win" "$x" "$y"
    sleep 0.5
    xdotool mousedown 1
    sleep 0.5
    for i in $(seq 1 "$n"); do
        xdotool mousemove --window "$win" $((x + i * dx)) $((y + i * dy))
        sleep 0.04
    done
    sleep 0.5
    xdotool mouseup 1
    sleep 0.5
}
drag 450 420 9 -1 40   # the groove
xdotool key 3           # paint
drag 480 520 10 0 30   # the band
xdotool key Escape
wait "$app" || { echo "desk_carve_strip: the session failed: $(tail -3 "$work/run.log")" >&2; exit 1; }
app=""
"$tridex" replay "$work/desk_carve.trdx" --strip "$png" --out "$work/replay" --width 320 --height 240
echo "desk_carve_strip: wrote $png from $work/desk_carve.trdx"
