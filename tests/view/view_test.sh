#!/usr/bin/env bash
# caustica view under Xvfb on lavapipe, validation on (any message makes view exit 3), in the
# sanitizer run (the pictures it shows are compared with headless renders by view_pixels_test.sh,
# in the Release run):
# 1. while orbiting the lights' passes are reused and moving one light of three runs its passes
#    alone, over the budget the size steps down, at rest the progressive graph refines apart, level by
#    level, and rests once converged;
# 2. an edit of the graph file is picked up while the viewer runs (within a second or two);
# 3. a broken edit keeps the old graph running, shows the error with its location, and the viewer
#    still exits 0 when closed (Ctrl-C);
# 4. a broken shader keeps the last good pipelines, a mended one is picked up;
# 5. so for a user pass's shader beside its graph, and only the passes it touches run again.
set -euo pipefail
bin=$1
src=$2
DISPLAY_BASE=90 source "$(dirname "$0")/xvfb.sh"
# The sphere on its plane: every viewer feature here is the same on it, and its frames cost a
# third of the bunny's (whose 70k triangles the light-space passes draw every frame).
scene="$src/scenes/sphere_plane.json"
# Light-space maps of 256 texels instead of the graphs' 1024: what is checked here is what the
# viewer runs and when, not the maps' detail, and a fresh 1024^2 map's first touch is most of a
# sanitized frame's cost.
small_maps=(--set light_size=256 --set shadow_size=256)

# 2 and 3. Hot reload, then a broken edit.
# A scripted orbit (without the frame budget, whose size changes start a new plan): after the first
# frame only the passes that see the camera run, the lights' keep their results (reused); with
# --every-pass every pass runs every frame.
# On three lights, the second moving too (--light 1, as L then the arrows do): its passes run, the
# other lights' keep their results.
lights="$src/scenes/three_lights.json"
"$bin" view --scene "$lights" --size 160x90 "${small_maps[@]}" --frames 3 --orbit 5 --light 1 --move-light 0.05 --budget 0 --stats "$dir/orbit.json" --validate > "$dir/log" 2>&1 || fail "view --orbit --light 1 --move-light exited $?: $(cat "$dir/log")"
"$bin" view --scene "$scene" --size 160x90 "${small_maps[@]}" --frames 3 --orbit 5 --budget 0 --every-pass --stats "$dir/every.json" --validate > "$dir/log" 2>&1 || fail "view --every-pass exited $?"
# A budget no frame meets: after the first frame not the first of its plan (a new plan's first frame
# runs every pass, the light's too, and says little of the frames after it) the budget goes straight
# to the cheapest step, a quarter of the size with the default graph's while_moving values (a frame
# over 2^2 times the budget predicts that no size step fits: editor/model/frame_budget.h).
"$bin" view --scene "$scene" --size 160x90 "${small_maps[@]}" --frames 7 --orbit 5 --budget 1 --stats "$dir/budget.json" --validate > "$dir/log" 2>&1 || fail "view --budget exited $?"
python3 - "$dir/orbit.json" "$dir/every.json" "$dir/budget.json" <<'PY' || fail "the frame logs do not show the light's passes reused while orbiting, or the budget's sizes"
import json, sys
orbit, every, budget = (json.load(open(f)) for f in sys.argv[1:])
assert [f["divider"] for f in budget["frames"]] == [1, 1, 4, 4, 4, 4, 4], budget["frames"]
assert [f["lowered"] for f in budget["frames"]] == [False] * 2 + [True] * 5, budget["frames"]  # with the graph's while_moving values
assert all(f["divider"] == 1 for f in orbit["frames"] + every["frames"]), "--budget 0 lowered the size"
assert orbit["summary"]["frames"] == 3 and orbit["summary"]["moving_frames"] == 3, orbit["summary"]
assert not orbit["frames"][0]["reused"], orbit["frames"][0]
for f in orbit["frames"][1:]:
    assert {"shadow#0", "caustics#0", "shadow#2", "caustics#2"} <= set(f["reused"]), f
    assert {"gbuffer", "tonemap", "lighting", "shadow#1", "receivers#1", "light_refractors#1", "caustics#1"} <= set(f["ran"]), f
assert all(not f["reused"] for f in every["frames"]), every["frames"]
assert all(f["wall_ms"] > 0 for f in orbit["frames"] + every["frames"])
PY
echo "ok: while orbiting, the lights' passes are reused but those of the one that moves; --every-pass runs them all; over the budget the cheapest step at once"

# A light the scene does not have is refused, naming the scene.
status=0
"$bin" view --scene "$lights" --size 160x90 --frames 1 --light 3 > "$dir/log" 2>&1 || status=$?
[ "$status" -eq 1 ] && grep -q "three_lights.json: --light 3: the scene has 3 lights (from 0)" "$dir/log" || fail "view --light 3 on three lights: exit $status, $(cat "$dir/log")"
echo "ok: --light 3 on three lights is refused"

# The progressive graph at rest and moving (its still pictures: view_pixels_test.sh).
progressive="$src/graphs/caustics_progressive.json"
# At rest with a budget that no whole frame meets, frames refine the mean (the caustic passes alone)
# from the second on, the first frame's GPU time standing for a whole frame's (a second whole frame
# to measure it was one more over the budget), and now and then show it (the camera's passes alone,
# one a frame since each is over the budget); three refining frames over the budget take the next of
# slice_side's while_still values (2, 3, 4: a new plan, whose first frame does not run whole, its
# showing passes' pictures carried over; slice_side is sampling-only, so the mean goes on), up to
# the last; the last frame runs whole. (That the mean carried across slices is the one of as many
# photons: Progressive.AMeanGoesOnWhenTheSliceChanges.)
"$bin" view --scene "$scene" --graph "$progressive" --size 160x90 "${small_maps[@]}" --frames 30 --still-after 0 --budget 1 --stats "$dir/apart.json" --validate > "$dir/log" 2>&1 || fail "view of the progressive graph with --budget 1 exited $?"
grep -q "view: refining frames too slow for the 1 ms budget (median .* ms): the while_still values of level 3 of 3" "$dir/log" || fail "no message of the last level: $(cat "$dir/log")"
python3 - "$dir/apart.json" <<'PY' || fail "the frame log does not show refining frames apart at rest, at each level in turn"
import json, sys
frames = json.load(open(sys.argv[1]))["frames"]
parts = [f["part"] for f in frames]
assert parts[0] == "whole" and parts[1] != "whole" and parts[-1] == "whole" and "refine" in parts, parts
for f in frames:
    if f["part"] == "refine": assert f["ran"] == ["caustics#0", "accumulate#0"], f
    if f["part"] == "display": assert f["ran"], f  # a step that runs nothing would be a frame lost
# With every pass over the budget, a display shows in steps of one pass each, in order.
shown = [p for f in frames if f["part"] == "display" for p in f["ran"]]
cycle = ["lighting", "refraction", "tonemap"]
assert shown == [cycle[i % 3] for i in range(len(shown))], shown
# Each level is judged on three refining frames; a new level's first frame does not run whole (it
# refines, or shows the mean where a display came due, as on a slow build).
levels = [f["still_level"] for f in frames]
assert levels == sorted(levels) and levels[-1] == 2, levels
for level in (0, 1):
    assert sum(f["part"] == "refine" for f in frames if f["still_level"] == level) == 3, levels
    assert frames[levels.index(level + 1)]["part"] != "whole", parts
# The mean goes on through the levels: every frame that refines it (not a display step) adds one.
counted = [f["accumulated"] for f in frames if f["part"] != "display"]
assert counted == list(range(1, len(counted) + 1)), counted
# A frame that leaves the picture as it was goes to the window only every quarter second (the
# panel's numbers): a frame that changes it always does. (A refining frame well within the quarter
# second leaves one unpresented; a slow build's, over it, may all be presented.)
for f in frames:
    if f["part"] == "whole" or (f["part"] == "display" and f["ran"][-1] == "tonemap"): assert f["presented"], f
if any(f["part"] == "refine" and f["wall_ms"] < 200 for f in frames):
    assert not all(f["presented"] for f in frames if f["part"] == "refine"), frames
unpresented_ms = 0
for f in frames:
    unpresented_ms = 0 if f["presented"] else unpresented_ms + f["wall_ms"]
    assert unpresented_ms < 250, frames
PY
# Resting, orbiting and resting again: the still plan's mean goes on where it stood (it is parked
# while the moving plan averages its own photons, and the camera is not what it depends on).
"$bin" view --scene "$scene" --graph "$progressive" --size 160x90 "${small_maps[@]}" --frames 10 --still-after 0 --budget 0 --orbit 5 --move-frames 4:6 --stats "$dir/rest_orbit.json" --validate > "$dir/log" 2>&1 || fail "view --move-frames exited $?: $(cat "$dir/log")"
python3 - "$dir/rest_orbit.json" <<'PY' || fail "the still mean did not go on after an orbit"
import json, sys
frames = json.load(open(sys.argv[1]))["frames"]
assert [f["moving"] for f in frames] == [False] * 4 + [True] * 2 + [False] * 4, frames
assert [f["accumulated"] for f in frames] == [1, 2, 3, 4, 1, 2, 5, 6, 7, 8], [f["accumulated"] for f in frames]
PY
# Left still after a move, with a budget no whole frame meets: the while_still values are a new
# plan whose camera passes show another caustic method, and its first frame refines at once, the
# moving frame's picture standing until a display shows the still mean (which goes on from before
# the move). Without the picture let stand, that frame ran whole. (The move is on the frame after
# the plan's first, which the budget does not judge: the moving frame keeps the still one's size
# on a slow build too.)
"$bin" view --scene "$scene" --graph "$progressive" --size 160x90 "${small_maps[@]}" --frames 4 --still-after 0 --budget 1 --orbit 5 --move-frames 1:2 --stats "$dir/stop.json" --validate > "$dir/log" 2>&1 || fail "view --budget 1 --move-frames exited $?: $(cat "$dir/log")"
python3 - "$dir/stop.json" <<'PY' || fail "the first still frame after a move did not refine with the picture standing"
import json, sys
frames = json.load(open(sys.argv[1]))["frames"]
assert [f["moving"] for f in frames] == [False, True, False, False], frames
assert frames[1]["part"] == "whole" and frames[1]["presented"], frames[1]
assert frames[2]["still"] and frames[2]["part"] == "refine" and frames[2]["ran"] == ["caustics#0", "accumulate#0"], frames[2]
assert frames[2]["accumulated"] == 2, frames[2]
PY
"$bin" view --graph "$progressive" --size 160x90 --frames 1 --set distanse=search > "$dir/log" 2>&1 && fail "view --set with an unknown parameter exited 0"
grep -q "has no parameter 'distanse' (did you mean 'distance'?)" "$dir/log" || fail "view --set distanse=search: $(cat "$dir/log")"
# A graph that does not compile at the start: its message and exit 1, and no claim of last good files.
printf '{"name": "broken", "passes": [], "outputs": []}\n' > "$dir/broken.json"
"$bin" view --graph "$dir/broken.json" --size 160x90 --frames 1 > "$dir/log" 2>&1 && fail "view of a broken graph exited 0"
grep -q "broken.json" "$dir/log" || fail "view of a broken graph does not name it: $(cat "$dir/log")"
if grep -q "kept the last good" "$dir/log"; then fail "view of a broken graph claims to keep last good files: $(cat "$dir/log")"; fi
"$bin" view --graph "$progressive" --size 160x90 "${small_maps[@]}" --frames 3 --orbit 5 --still-after 0 --stats "$dir/moving.json" --validate > "$dir/log" 2>&1 || fail "view --orbit of the progressive graph exited $?"
# Ray queries asked for (--tracer ray_query) on a device without them refuse the exact photons: the
# values as set, and a message. (Without --tracer the compute tracer traces them.)
CAUSTICA_NO_RAY_QUERY=1 "$bin" view --tracer ray_query --scene "$scene" --graph "$progressive" --size 160x90 "${small_maps[@]}" --frames 2 --still-after 0 --stats "$dir/refused.json" --validate > "$dir/log" 2>&1 || fail "view of the progressive graph without ray queries exited $?"
grep -q "view: not using the while_still values: .*VK_KHR_ray_query" "$dir/log" || fail "no message that the while_still values were refused: $(cat "$dir/log")"
python3 - "$dir/moving.json" "$dir/refused.json" <<'PY' || fail "the frame logs do not show the while_still values at rest only, or the converging frames"
import json, sys
moving, refused = (json.load(open(f))["frames"] for f in sys.argv[1:])
assert all(f["moving"] and not f["still"] for f in moving), moving
assert all(not f["still"] and f["converging"] for f in refused), refused
PY
echo "ok: at rest the progressive graph accumulates exact photons (its while_still values) and keeps drawing"

wait_for() {  # TEXT SECONDS: until the log holds TEXT; prints the seconds it took
  local start=$SECONDS
  for _ in $(seq $(($2 * 20))); do
    if grep -qF -- "$1" "$dir/log"; then echo $((SECONDS - start)); return 0; fi
    kill -0 "$view_pid" 2>/dev/null || fail "view exited while waiting for '$1'"
    sleep 0.05
  done
  fail "no '$1' within $2 s"
}

# At rest the viewer draws on while the mean converges, and then rests: with max_frames 6 (more
# than the few frames any change is given) it says so after the sixth still frame and then draws
# at most those few more. Without a frame budget, so that a loaded machine's slow frames take no
# cheaper while_still level (a new plan, whose mean starts again).
python3 -c 'import json, sys; g = json.load(open(sys.argv[1])); g["parameters"]["max_frames"]["default"] = 6; json.dump(g, open(sys.argv[2], "w"), indent=2)' \
  "$progressive" "$dir/prog6.json"
"$bin" view --scene "$scene" --graph "$dir/prog6.json" --size 160x90 "${small_maps[@]}" --still-after 0 --budget 0 --validate > "$dir/log" 2>&1 &
view_pid=$!
wait_for "view: converged after 6 frames at rest" 120 > /dev/null
sleep 1
kill -INT "$view_pid"
wait "$view_pid" || fail "view of the progressive graph exited $? after Ctrl-C"
view_pid=""
drawn=$(sed -n 's/^view: \([0-9]*\) frames drawn$/\1/p' "$dir/log")
[ -n "$drawn" ] && [ "$drawn" -le 10 ] || fail "the viewer did not rest after converging: ${drawn:-?} frames drawn"
echo "ok: at rest the viewer draws until the mean has converged (6 frames), then rests ($drawn frames in all)"

cp "$src/graphs/core_demo.json" "$dir/g.json"
"$bin" view --graph "$dir/g.json" --size 160x90 --validate > "$dir/log" 2>&1 &
view_pid=$!
wait_for "view: loaded $dir/g.json" 120 > /dev/null
# The window's title names the graph and the scene (the default scene here).
xdotool search --name '^caustica: core_demo on glass_bunny$' > /dev/null || fail "no window titled 'caustica: core_demo on glass_bunny'"
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
wait_for "view: reloaded color.glsl" 5 > /dev/null
echo "ok: the mended shader is picked up"
kill -INT "$view_pid"
status=0
wait "$view_pid" || status=$?
view_pid=""
[ "$status" -eq 0 ] || fail "view exited $status after the shader edits"

# 5. A user pass's shader, beside its graph: saved broken, the last good plan runs on with the
#    error naming the user's file and line; mended, only the user pass and what reads its output run
#    again (the pattern and the first blur keep their results).
mkdir "$dir/user"
sed -e 's#"type": "box_blur", "params": {"radius": "$blur_radius", "axis": "y"}#"type": "compute", "shader": "scale.comp", "ports": {"source": {"access": "read"}, "target": {"access": "write", "formats": ["rgba16f"]}}, "parameters": {"gain": {"type": "float", "default": 1}}, "dispatch": "target", "params": {"gain": 1}#' \
    -e 's#"\$schema": "./schema.json",##' "$src/graphs/core_demo.json" > "$dir/user/g.json"
grep -q '"compute"' "$dir/user/g.json" || fail "the user-pass graph was not made from core_demo.json"
scale_shader() {  # GAIN
  cat > "$dir/user/scale.comp" <<GLSL
#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D source;
layout(binding = 1, rgba16f) uniform writeonly image2D target;
layout(push_constant) uniform Params { float gain; } params;
void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(target)))) return;
  imageStore(target, p, $1 * params.gain * texelFetch(source, p, 0));
}
GLSL
}
scale_shader 1.0
: > "$dir/log"
"$bin" view --graph "$dir/user/g.json" --size 160x90 --validate --stats "$dir/user/stats.json" > "$dir/log" 2>&1 &
view_pid=$!
wait_for "view: loaded" 120 > /dev/null
sleep 1
sed -i 's/imageStore(target/imageStore(targte/' "$dir/user/scale.comp"
wait_for "view: kept the last good shaders: " 5 > /dev/null
grep -q "scale.comp:9:" "$dir/log" || fail "the user shader's error does not name its file and line"
echo "ok: a broken user shader keeps the last good plan and names its file and line"
scale_shader 0.5
wait_for "view: reloaded scale.comp" 5 > /dev/null
sleep 1
kill -INT "$view_pid"
status=0
wait "$view_pid" || status=$?
view_pid=""
[ "$status" -eq 0 ] || fail "view exited $status after the user shader edits"
python3 - "$dir/user/stats.json" <<'PY' || fail "the mended user shader did not run alone with what reads its output"
import json, sys
frames = [f for f in json.load(open(sys.argv[1]))["frames"] if f["ran"]]  # redraws of an unchanged frame run nothing
assert sorted(frames[0]["ran"]) == ["blur_x", "blur_y", "pattern", "tonemap"], frames[0]
assert sorted(frames[-1]["ran"]) == ["blur_y", "tonemap"], frames[-1]
assert sorted(frames[-1]["reused"]) == ["blur_x", "pattern"], frames[-1]
PY
echo "ok: the mended user shader is picked up, and only it and the tone map run again"
