#!/usr/bin/env bash
# caustica edit under Xvfb on lavapipe, validation on (any message makes it exit 3): an edit script
# opens core_demo.json, adds a pass, connects it (the frame changes), breaks a connection (refused,
# with the message), saves, and the file is compared; Ctrl+Z and Ctrl+S are real key taps (xdotool).
# Then the viewer: idle CPU far below a rendering loop's, and a 10 ms key tap is never lost.
set -euo pipefail
bin=$1
src=$2
DISPLAY_BASE=190 source "$(dirname "$0")/xvfb.sh"
cd "$dir"

# Every wait for the editor's answer to a tap or a drag allows a minute: under AddressSanitizer on
# a loaded machine one frame has taken seconds (a 5 s wait once failed the mouse drag in CI).

# 1. The edit script: every action goes through the editor as the canvas does it.
cp "$src/graphs/core_demo.json" g.json
cat > script.txt <<'SCRIPT'
screenshot before.png
add box_blur 600 300
connect box_blur source blurred
connect tonemap source box_blur_target
screenshot after.png
disconnect tonemap source
save
SCRIPT
"$bin" edit g.json --size 320x180 --frames 10 --script script.txt --validate > log 2>&1 || fail "edit exited $?"
grep -q "edit: add box_blur 600 300: ok" log || fail "the pass was not added"
grep -q "edit: connect tonemap source box_blur_target: ok" log || fail "the connection was refused"
if "$bin" compare before.png after.png --max-l1 0.001 > /dev/null 2>&1; then fail "the frame did not change after the edit"; fi
grep -q "edit: disconnect tonemap source: refused: .*input 'source' of pass 'tonemap' (type tonemap) is not connected" log ||
  fail "breaking a required connection was not refused with the compiler's message"
echo "ok: add, connect (the frame changed), a broken connection refused with its message"
# The saved file: core_demo.json with the new pass, its resource, the new wiring and its position,
# and every other line as it was written.
"$bin" validate g.json > /dev/null || fail "the saved graph does not validate"
python3 - g.json <<'PY' || fail "the saved file does not hold the edit"
import json, sys
b = json.load(open(sys.argv[1]))
assert b["passes"][3]["inputs"]["source"] == "box_blur_target", b["passes"][3]
assert b["passes"][-1]["name"] == "box_blur" and b["passes"][-1]["inputs"]["source"] == "blurred"
assert b["editor"]["positions"]["box_blur"] == [600, 300]
assert b["resources"]["box_blur_target"]["format"] == "rgba16f"
PY
# A user pass from its shader file alone, as the menu's "compute: compute shader..." adds it: its
# ports come from the shader's bindings, and wired in before the tone map it changes the frame.
cp "$src/graphs/core_demo.json" user.json
cat > half.comp <<'GLSL'
#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D source;
layout(binding = 1, rgba16f) uniform writeonly image2D target;
void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(target)))) return;
  imageStore(target, p, 0.5 * texelFetch(source, p, 0));
}
GLSL
printf 'screenshot user_before.png\nadd-shader compute half.comp 600 300\nconnect tonemap source compute_target\nscreenshot user_after.png\nsave\n' > user.txt
"$bin" edit user.json --size 320x180 --frames 10 --script user.txt --validate > log 2>&1 || fail "edit exited $? adding a user pass"
grep -q "edit: add-shader compute half.comp 600 300: ok" log || fail "the user pass was not added from its shader"
grep -q "edit: connect tonemap source compute_target: ok" log || fail "the user pass's output could not be wired to the tone map"
if "$bin" compare user_before.png user_after.png --max-l1 0.01 > /dev/null 2>&1; then fail "the user pass did not change the frame"; fi
"$bin" validate user.json > /dev/null || fail "the graph saved with a user pass does not validate"
python3 - user.json <<'PY' || fail "the saved user pass is not declared from its shader"
import json, sys
p = json.load(open(sys.argv[1]))["passes"][-1]
assert p["type"] == "compute" and p["shader"] == "half.comp" and p["dispatch"] == "target", p
assert p["ports"] == {"source": {"access": "read"}, "target": {"access": "write", "formats": ["rgba16f"]}}, p["ports"]
PY
echo "ok: a user pass added from its shader, its ports from the shader's bindings, changes the frame"
# Byte for byte: the expected file is core_demo.json with only the script's edit, written out by
# hand (see its diff against core_demo.json): the tonemap's inputs line; "box_blur_target"
# {type image, format rgba16f} after "preview" (no width or height: it follows "blurred", which
# has none); the box_blur pass (its type's default params, source "blurred", target
# "box_blur_target") after "unused_preview"; "editor": {"positions": {"box_blur": [600, 300]}}
# after "outputs"; a comma after each member that is no longer last. New members are written as
# the writer writes fresh values (dump with the file's indent). Any other line removed, changed or
# added fails. If graphs/core_demo.json itself changes, this file must change with it.
expected="$src/tests/data/edit/core_demo_after_edit.json"
if ! cmp -s "$expected" g.json; then
  diff -u "$expected" g.json | sed 's/^/  /' >&2 || true
  fail "the saved file is not tests/data/edit/core_demo_after_edit.json byte for byte (diff above: - expected, + saved)"
fi
echo "ok: the saved file is the original with exactly the edit"

# The default window (1600x900) on caustics_adaptive, as drawn: the dock under half of the window,
# every node inside the canvas, no wire label over a node or another label, and the canvas's text at
# the panels' size (issue 43: text 6 px high, passes outside the canvas, labels over nodes).
cp "$src/graphs/caustics_adaptive.json" legible.json
printf 'layout\n' > layout.txt
"$bin" edit legible.json --frames 4 --script layout.txt > log 2>&1 || fail "edit exited $?"
python3 - log <<'PY' || fail "the default window's canvas is not legible (above)"
import re, sys
boxes = {"dock": [], "canvas": [], "node": [], "label": []}
text = None
for line in open(sys.argv[1]):
    m = re.match(r"edit: (dock|canvas|node|label) (.+) at (-?\d+),(-?\d+) size (\d+)x(\d+)$", line.strip())
    if m:
        boxes[m[1]].append((m[2],) + tuple(int(v) for v in m.groups()[2:]))
    t = re.match(r"edit: canvas text (\d+) px, panel text (\d+) px", line)
    if t:
        text = (int(t[1]), int(t[2]))
assert boxes["dock"] and boxes["canvas"] and len(boxes["node"]) == 8, boxes
(_, dx, dy, dw, dh), (_, cx, cy, cw, ch) = boxes["dock"][0], boxes["canvas"][0]
assert (dw, dy + dh) == (1600, 900) and dh <= 450, f"the dock {dw}x{dh} at y {dy} hides more than half of the picture"
assert text and text[0] >= text[1], f"canvas text {text}"
def inside(b):
    return b[1] >= cx and b[2] >= cy and b[1] + b[3] <= cx + cw and b[2] + b[4] <= cy + ch
def overlap(a, b):
    return a[1] < b[1] + b[3] and b[1] < a[1] + a[3] and a[2] < b[2] + b[4] and b[2] < a[2] + a[4]
for n in boxes["node"]:
    assert inside(n), f"node {n} outside the canvas {cx},{cy} {cw}x{ch}"
labels = boxes["label"]
assert labels, "no wire labelled"
for i, l in enumerate(labels):
    for n in boxes["node"]:
        assert not overlap(l, n), f"label {l} over node {n}"
    for k in labels[i + 1:]:
        assert not overlap(l, k), f"label {l} over label {k}"
print(f"ok: dock {dw}x{dh}, canvas {cw}x{ch}, {len(boxes['node'])} nodes inside, {len(labels)} labels clear, text {text[0]} px")
PY

# A graph that does not compile (core_demo without the tonemap's input) opens refused with the
# compiler's message and a black picture; an edit repairs it, the picture comes back, and it saves
# (issue 43: the editor exited 1 on it).
python3 - "$src/graphs/core_demo.json" broken.json <<'PY'
import json, sys
graph = json.load(open(sys.argv[1]))
del graph["passes"][3]["inputs"]
json.dump(graph, open(sys.argv[2], "w"), indent=2)
PY
printf 'screenshot refused.png\nset blur_x radius 5\nconnect tonemap source blurred\nscreenshot repaired.png\nsave\n' > repair.txt
"$bin" edit broken.json --size 320x180 --frames 10 --script repair.txt --validate > log 2>&1 || fail "edit exited $? on a graph that does not compile"
grep -q "edit: broken.json opens refused, to be repaired: .*input 'source' of pass 'tonemap'" log ||
  fail "the graph was not opened refused with the compiler's message"
grep -q "edit: set blur_x.radius (the graph is still refused)" log || fail "an edit that leaves the graph refused was not taken"
grep -q "edit: connect tonemap source blurred: ok" log || fail "the repairing edit was refused"
"$bin" validate broken.json > /dev/null || fail "the repaired and saved graph does not validate"
if "$bin" compare refused.png repaired.png --max-l1 0.001 > /dev/null 2>&1; then fail "the picture did not change when the graph was repaired"; fi
echo "ok: a graph that does not compile opens refused, an edit repairs it, and it saves"

# 2. Real keys: Ctrl+Z undoes the last edit, Ctrl+S saves it, with the editor idle between taps.
cp "$src/graphs/core_demo.json" k.json
printf 'set blur_x radius 9\n' > one.txt
"$bin" edit k.json --size 320x180 --script one.txt > log 2>&1 &
view_pid=$!
for _ in $(seq 600); do grep -q "edit: set blur_x radius 9: ok" log && break; kill -0 $view_pid || fail "edit exited"; sleep 0.1; done
grep -q "edit: set blur_x radius 9: ok" log || fail "the script did not run"
window=$(xdotool search --sync --name '^caustica: ' | head -1)
xdotool key --window "$window" ctrl+z
sleep 1
xdotool key --window "$window" ctrl+s
for _ in $(seq 600); do grep -q "edit: saved" log && break; sleep 0.1; done
grep -q "edit: saved" log || fail "Ctrl+S did not save"
cmp -s k.json "$src/graphs/core_demo.json" || fail "Ctrl+Z then Ctrl+S did not give back the original file"
kill -INT $view_pid; wait $view_pid || fail "edit exited $? after Ctrl-C"
view_pid=""
echo "ok: Ctrl+Z and Ctrl+S from the keyboard"

# A file another editor changed meanwhile is not overwritten by Ctrl+S: the editor asks first.
cp "$src/graphs/core_demo.json" other.json
: > log
"$bin" edit other.json --size 320x180 --script one.txt > log 2>&1 &
view_pid=$!
for _ in $(seq 600); do grep -q "edit: set blur_x radius 9: ok" log && break; kill -0 $view_pid || fail "edit exited"; sleep 0.1; done
printf '\n' >> other.json
cp other.json changed_elsewhere.json
window=$(xdotool search --sync --name '^caustica: ' | head -1)
xdotool key --window "$window" ctrl+s
for _ in $(seq 600); do grep -q "changed on disk since it was opened: overwrite it?" log && break; sleep 0.1; done
grep -q "changed on disk since it was opened: overwrite it?" log || fail "Ctrl+S did not ask before overwriting a file changed on disk"
cmp -s other.json changed_elsewhere.json || fail "the file changed on disk was overwritten without a confirmation"
kill -INT $view_pid; wait $view_pid || fail "edit exited $? after Ctrl-C"
view_pid=""
echo "ok: a file changed on disk is not overwritten without a confirmation"

# The canvas with a real mouse: drag from an output port to an input port connects them; Del over
# the canvas removes the selected pass (selected by the script). The script logs where it drew the ports.
cp "$src/graphs/core_demo.json" mouse.json
printf 'add box_blur 700 100\nwhere blur_y.target\nwhere box_blur.source\nselect box_blur\n' > ports.txt
: > log
# At two frames a second (--max-fps 2 --continuous), with the mouse moved on at once after the
# press: the click must land where the button went down, not where the mouse is at the next frame.
"$bin" edit mouse.json --size 1280x720 --continuous --max-fps 2 --script ports.txt > log 2>&1 &
view_pid=$!
for _ in $(seq 600); do grep -q "edit: select box_blur: ok" log && break; kill -0 $view_pid || fail "edit exited"; sleep 0.1; done
from=$(sed -n 's/^edit: port blur_y.target at \([0-9]*\),\([0-9]*\)$/\1 \2/p' log)
to=$(sed -n 's/^edit: port box_blur.source at \([0-9]*\),\([0-9]*\)$/\1 \2/p' log)
[ -n "$from" ] && [ -n "$to" ] || fail "the ports were not drawn on the canvas"
window=$(xdotool search --sync --name '^caustica: ' | head -1)
xdotool mousemove --window "$window" $from
sleep 1.5
xdotool mousedown 1 mousemove --window "$window" $to
sleep 1.5
xdotool mouseup 1
for _ in $(seq 600); do grep -q "edit: connect box_blur.source to blurred" log && break; sleep 0.1; done
grep -q "edit: connect box_blur.source to blurred" log || fail "dragging from blur_y.target to box_blur.source did not connect them"
xdotool key --window "$window" Delete
for _ in $(seq 600); do grep -q "edit: remove box_blur" log && break; sleep 0.1; done
grep -q "edit: remove box_blur" log || fail "Del did not remove the selected pass"
# Right click on the canvas opens the menu of pass types; typing filters it, Enter adds the first.
xdotool click 3
for _ in $(seq 600); do grep -q "edit: the pass-type menu has the keyboard" log && break; sleep 0.1; done
grep -q "edit: the pass-type menu has the keyboard" log || fail "right click did not open the menu of pass types"
xdotool type --delay 30 "tonemap"
xdotool key --window "$window" Return
for _ in $(seq 600); do grep -q "edit: add tonemap" log && break; sleep 0.1; done
grep -q "edit: add tonemap" log || fail "the menu of pass types did not add a tonemap pass"
kill -INT $view_pid; wait $view_pid || fail "edit exited $? after Ctrl-C"
view_pid=""
echo "ok: drag port to port connects, Del removes, the right-click menu adds (real mouse and keys)"

# 3. The viewer at rest: CPU over 3 s with no input, against the same window rendering continuously
# beside it (both at once, each its own process: the resting one's CPU is its own, and the test
# does not wait twice).
cpu_seconds() { awk '{print ($14 + $15) / 100}' "/proc/$1/stat"; }
"$bin" view --size 320x180 --graph "$src/graphs/core_demo.json" > rest.log 2>&1 &
rest_pid=$!
"$bin" view --size 320x180 --graph "$src/graphs/core_demo.json" --continuous > busy.log 2>&1 &
busy_pid=$!
view_pid="$rest_pid $busy_pid"
for _ in $(seq 600); do grep -q "view: loaded" rest.log && grep -q "view: loaded" busy.log && break; sleep 0.1; done
sleep 2
rest_start=$(cpu_seconds $rest_pid) busy_start=$(cpu_seconds $busy_pid)
sleep 3
resting=$(awk -v a="$rest_start" -v b="$(cpu_seconds $rest_pid)" 'BEGIN { print b - a }')
busy=$(awk -v a="$busy_start" -v b="$(cpu_seconds $busy_pid)" 'BEGIN { print b - a }')
kill -INT $rest_pid $busy_pid; wait $rest_pid $busy_pid || true
view_pid=""
echo "viewer CPU over 3 s: at rest ${resting}s, continuous ${busy}s"
awk -v r="$resting" 'BEGIN { exit !(r < 0.15) }' || fail "the resting viewer used ${resting}s of CPU in 3 s (limit 0.15: 5% of a core)"
awk -v r="$resting" -v b="$busy" 'BEGIN { exit !(b > 5 * r && b > 0.3) }' || fail "the check cannot tell rest (${resting}s) from rendering (${busy}s)"
echo "ok: the resting viewer sleeps"

# 4. A 10 ms tap of P (screenshot) is never lost, at any frame rate: here a slow graph, continuous.
: > log
"$bin" view --size 640x360 --continuous > log 2>&1 &
view_pid=$!
for _ in $(seq 600); do grep -q "view: loaded" log && break; sleep 0.1; done
window=$(xdotool search --sync --name '^caustica: ' | head -1)
for i in 1 2 3; do
  xdotool keydown --window "$window" p
  sleep 0.01
  xdotool keyup --window "$window" p
  sleep 0.7
done
for _ in $(seq 600); do [ "$(grep -c 'view: screenshot' log)" -ge 3 ] && break; sleep 0.1; done
kill -INT $view_pid; wait $view_pid || true
view_pid=""
taps=$(grep -c "view: screenshot" log || true)
[ "$taps" -eq 3 ] || fail "$taps of 3 key taps of 10 ms were seen"
echo "ok: 3 of 3 taps of 10 ms seen"
