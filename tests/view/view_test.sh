#!/usr/bin/env bash
# caustica view under Xvfb on lavapipe, validation on (any message makes view exit 3):
# 1. --frames N --screenshot writes the frame the headless render of the same graph gives, and
#    --inspect shows the image that render --dump writes;
# 2. an edit of the graph file is picked up while the viewer runs (within a second or two);
# 3. a broken edit keeps the old graph running, shows the error with its location, and the viewer
#    still exits 0 when closed (Ctrl-C);
# 4. a broken shader keeps the last good pipelines, a mended one is picked up.
set -euo pipefail
bin=$1
src=$2
DISPLAY_BASE=90 source "$(dirname "$0")/xvfb.sh"

# 1. The screenshot is the headless render of the same graph and scene at the window's size.
"$bin" view --size 160x90 --frames 3 --screenshot "$dir/shot.png" --validate > "$dir/log" 2>&1 || fail "view --screenshot exited $?"
"$bin" render --size 160x90 --out "$dir/headless.png" 2> /dev/null
"$bin" compare "$dir/shot.png" "$dir/headless.png" --max-l1 0.001 > /dev/null || fail "the screenshot differs from the headless render"
echo "ok: screenshot matches the headless render"

# The resource inspector shows any image of the graph: the lit G-buffer as render --dump writes it.
"$bin" view --size 160x90 --frames 2 --inspect lit --screenshot "$dir/lit_view.exr" --validate > "$dir/log" 2>&1 || fail "view --inspect exited $?"
"$bin" render --size 160x90 --dump "lit=$dir/lit_dump.exr" --out "$dir/frame.png" 2> /dev/null
"$bin" compare "$dir/lit_view.exr" "$dir/lit_dump.exr" --max-l1 0.001 > /dev/null || fail "the inspected image differs from --dump"
echo "ok: the inspector shows the image --dump writes"

# The inspector panel shows its image fitted into the window: cut out of a shot of the whole
# window (UI included), it is the headless render scaled down to the panel's size.
"$bin" view --size 1100x500 --frames 2 --inspect ldr --window-shot "$dir/window.png" --validate > "$dir/log" 2>&1 || fail "view --window-shot exited $?"
where=$(sed -n 's/^view: window shot .*; inspector image ldr at \([0-9]*\),\([0-9]*\) \([0-9]*\)x\([0-9]*\)$/\3x\4+\1+\2/p' "$dir/log")
[ -n "$where" ] || fail "view did not say where the inspector's image lies"
"$bin" render --size 1100x500 --out "$dir/full.png" 2> /dev/null
oiiotool "$dir/window.png" --cut "$where" -o "$dir/panel.png"
oiiotool "$dir/full.png" --resize "${where%%+*}" -o "$dir/expected_panel.png"
"$bin" compare "$dir/panel.png" "$dir/expected_panel.png" --max-l1 0.03 > "$dir/compare" 2>&1 || fail "the inspector panel does not show the image: $(cat "$dir/compare")"
# The same place in a shot without the inspector shows something else (the control must differ).
"$bin" view --size 1100x500 --frames 2 --window-shot "$dir/no_panel.png" --validate > "$dir/log" 2>&1 || fail "view --window-shot exited $?"
oiiotool "$dir/no_panel.png" --cut "$where" -o "$dir/no_panel_cut.png"
if "$bin" compare "$dir/no_panel_cut.png" "$dir/expected_panel.png" --max-l1 0.03 > /dev/null 2>&1; then fail "the check cannot tell a panel from none"; fi
echo "ok: the inspector panel shows the image, fitted ($where), in a shot of the whole window"
# Without a screenshot or the inspector the output reaches the window by a blit on the device, with
# no read-back: right of the main panel the window shows the headless render exactly.
grep -q "goes to the window by a blit on the device" "$dir/log" || fail "the device blit is not used: $(head -3 "$dir/log")"
oiiotool "$dir/no_panel.png" --cut 600x400+460+50 -o "$dir/window_cut.png"
oiiotool "$dir/full.png" --cut 600x400+460+50 -o "$dir/full_cut.png"
"$bin" compare "$dir/window_cut.png" "$dir/full_cut.png" --max-l1 0.001 > "$dir/compare" 2>&1 || fail "the blitted output differs: $(cat "$dir/compare")"
echo "ok: the output blitted into the window is the headless render"

# 2 and 3. Hot reload, then a broken edit.
# A scripted orbit (without the frame budget, whose size changes start a new plan): after the first
# frame only the passes that see the camera run, the light's keep their results (reused); with
# --every-pass every pass runs every frame.
"$bin" view --size 160x90 --frames 3 --orbit 5 --budget 0 --stats "$dir/orbit.json" --validate > "$dir/log" 2>&1 || fail "view --orbit exited $?"
"$bin" view --size 160x90 --frames 3 --orbit 5 --budget 0 --every-pass --stats "$dir/every.json" --validate > "$dir/log" 2>&1 || fail "view --every-pass exited $?"
# A budget no frame meets: each moving frame halves the rendered size for the next, to a quarter,
# and then the next takes the default graph's while_moving values.
"$bin" view --size 160x90 --frames 4 --orbit 5 --budget 1 --stats "$dir/budget.json" --validate > "$dir/log" 2>&1 || fail "view --budget exited $?"
python3 - "$dir/orbit.json" "$dir/every.json" "$dir/budget.json" <<'PY' || fail "the frame logs do not show the light's passes reused while orbiting, or the budget's sizes"
import json, sys
orbit, every, budget = (json.load(open(f)) for f in sys.argv[1:])
assert [f["divider"] for f in budget["frames"]] == [1, 2, 4, 4], budget["frames"]
assert [f["lowered"] for f in budget["frames"]] == [False, False, False, True], budget["frames"]  # then the graph's while_moving values
assert all(f["divider"] == 1 for f in orbit["frames"] + every["frames"]), "--budget 0 lowered the size"
assert orbit["summary"]["frames"] == 3 and orbit["summary"]["moving_frames"] == 3, orbit["summary"]
assert not orbit["frames"][0]["reused"], orbit["frames"][0]
for f in orbit["frames"][1:]:
    assert {"shadow", "caustics"} <= set(f["reused"]) and {"gbuffer", "tonemap"} <= set(f["ran"]), f
assert all(not f["reused"] for f in every["frames"]), every["frames"]
assert all(f["wall_ms"] > 0 for f in orbit["frames"] + every["frames"])
PY
echo "ok: while orbiting, the light's passes are reused; --every-pass runs them all; over the budget the size halves"

wait_for() {  # TEXT SECONDS: until the log holds TEXT; prints the seconds it took
  local start=$SECONDS
  for _ in $(seq $(($2 * 20))); do
    if grep -qF -- "$1" "$dir/log"; then echo $((SECONDS - start)); return 0; fi
    kill -0 "$view_pid" 2>/dev/null || fail "view exited while waiting for '$1'"
    sleep 0.05
  done
  fail "no '$1' within $2 s"
}
cp "$src/graphs/core_demo.json" "$dir/g.json"
"$bin" view --graph "$dir/g.json" --size 160x90 --validate > "$dir/log" 2>&1 &
view_pid=$!
wait_for "view: loaded $dir/g.json" 120 > /dev/null
sed -i 's/"default": 3,/"default": 5,/' "$dir/g.json"
grep -q '"default": 5,' "$dir/g.json" || fail "the test's edit did not apply"
took=$(wait_for "view: reloaded $dir/g.json" 3)
echo "ok: the edit was picked up (within ${took}s)"
printf '{ "broken": ' > "$dir/g.json"
wait_for "view: kept the last good files: $dir/g.json:1:" 3 > /dev/null
echo "ok: a broken edit keeps the last good graph and names the file and line"
kill -INT "$view_pid"
status=0
wait "$view_pid" || status=$?
view_pid=""
[ "$status" -eq 0 ] || fail "view exited $status after Ctrl-C (3: validation messages)"
echo "ok: the viewer kept running and exited 0"

# 4. Shaders: a broken shader keeps the last good pipelines, a fixed one is picked up. The viewer
#    reads a copy of the data folder, so the edit touches no shared file.
mkdir "$dir/data"
cp -r "$src/shaders" "$src/graphs" "$src/scenes" "$dir/data/"
export CAUSTICA_DATA_DIR="$dir/data"
shader="$dir/data/shaders/common/color.glsl"
cp "$shader" "$dir/color.glsl"
: > "$dir/log"
"$bin" view --graph "$dir/data/graphs/core_demo.json" --size 160x90 --validate > "$dir/log" 2>&1 &
view_pid=$!
wait_for "view: loaded" 120 > /dev/null
echo "this is not glsl" >> "$shader"
wait_for "view: kept the last good shaders: " 5 > /dev/null
grep -q "color.glsl:[0-9]*:" "$dir/log" || fail "the shader error does not name the file and line"
echo "ok: a broken shader keeps the last good pipelines and names the file and line"
cp "$dir/color.glsl" "$shader"
wait_for "view: reloaded shaders" 5 > /dev/null
echo "ok: the mended shader is picked up"
kill -INT "$view_pid"
status=0
wait "$view_pid" || status=$?
view_pid=""
[ "$status" -eq 0 ] || fail "view exited $status after the shader edits"
