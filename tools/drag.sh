#!/usr/bin/env bash
# Measures the viewer's frame budget under a hand's input, which a scripted --orbit (input every
# frame) does not show: a mouse drag whose events come RATE times a second (default 10), N events
# (default 80), on `caustica view` under an Xvfb of its own, then the moving frames' wall-time median
# and 95th percentile from its --stats log (docs/interactive.md keeps the numbers).
# Usage: tools/drag.sh CAUSTICA [RATE] [N] [-- extra view flags]   e.g. tools/drag.sh build/release/caustica 10 80
# Needs Xvfb and xdotool (tools/install-deps.sh). Uses display :94 (DRAG_DISPLAY overrides it) and the
# default graph and scene unless view flags say otherwise; DRAG_STATS=FILE keeps the frame log;
# DRAG_WAIT (default 12) is the seconds given to the viewer's first frame (pipelines compile then;
# more on a loaded machine or with a cold shader cache).
set -u
C=$1; RATE=${2:-10}; N=${3:-80}; shift $(( $# < 3 ? $# : 3 )); [ "${1:-}" = "--" ] && shift
command -v xdotool >/dev/null && command -v Xvfb >/dev/null || { echo "needs xvfb and xdotool"; exit 2; }
D=${DRAG_DISPLAY:-94}
T=$(mktemp -d); Xvfb ":$D" -screen 0 1280x800x24 -nolisten tcp >/dev/null 2>&1 & xp=$!
trap 'kill $xp 2>/dev/null; [ -n "${vp:-}" ] && kill -9 $vp 2>/dev/null; rm -rf "$T"' EXIT
sleep 1
DISPLAY=":$D" "$C" view --size 1280x720 --stats "$T/stats.json" "$@" >"$T/view.log" 2>&1 & vp=$!
sleep "${DRAG_WAIT:-12}"
kill -0 $vp 2>/dev/null || { echo "viewer exited: $(tail -n1 "$T/view.log")"; exit 1; }
export DISPLAY=":$D"
step=$(python3 -c "print(1.0 / $RATE)")
xdotool mousemove 640 360 mousedown 1
for i in $(seq 1 "$N"); do xdotool mousemove_relative -- 6 1; sleep "$step"; done
xdotool mouseup 1; sleep 3
kill $vp; wait $vp 2>/dev/null; vp=
[ -n "${DRAG_STATS:-}" ] && cp "$T/stats.json" "$DRAG_STATS"
python3 - "$T/stats.json" <<'PY'
import json, sys
fr = [f for f in json.load(open(sys.argv[1]))["frames"] if f.get("moving")]
w = sorted(f["wall_ms"] for f in fr)
full = sum(1 for f in fr if f["divider"] == 1 and f["wall_ms"] > 90)
print(f"moving frames {len(w)}: median {w[len(w) // 2]:.1f} ms, p95 {w[int(0.95 * (len(w) - 1))]:.1f} ms; {full} at full size over 90 ms")
PY
