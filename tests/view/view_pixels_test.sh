#!/usr/bin/env bash
# caustica view's pictures under Xvfb on lavapipe, validation on (any message makes view exit 3),
# against headless renders of the same graph, scene and size: what they compare is numbers, so this
# runs in the Release run (tests/CMakeLists.txt; view_test.sh runs the viewer's behaviour under the
# sanitizers).
# 1. --frames N --screenshot writes the frame the headless render of the same graph gives, and
#    --inspect shows the image that render --dump writes, in its panel too; the output reaches the
#    window by a device blit;
# 2. at rest the progressive graph's fourth still frame is four accumulated exact frames (its
#    while_still values), or four search frames where --set says so.
set -euo pipefail
bin=$1
src=$2
DISPLAY_BASE=70 source "$(dirname "$0")/xvfb.sh"
scene="$src/scenes/sphere_plane.json"

# 1. The screenshot is the headless render of the same graph and scene at the window's size.
"$bin" view --scene "$scene" --size 160x90 --frames 3 --screenshot "$dir/shot.png" --validate > "$dir/log" 2>&1 || fail "view --screenshot exited $?"
# The resource inspector shows any image of the graph: the lit G-buffer as render --dump writes it.
"$bin" view --scene "$scene" --size 160x90 --frames 2 --inspect lit --screenshot "$dir/lit_view.exr" --validate > "$dir/log" 2>&1 || fail "view --inspect exited $?"
"$bin" render --scene "$scene" --size 160x90 --dump "lit=$dir/lit_dump.exr" --out "$dir/headless.png" 2> /dev/null
"$bin" compare "$dir/shot.png" "$dir/headless.png" --max-l1 0.001 > /dev/null || fail "the screenshot differs from the headless render"
echo "ok: screenshot matches the headless render"
"$bin" compare "$dir/lit_view.exr" "$dir/lit_dump.exr" --max-l1 0.001 > /dev/null || fail "the inspected image differs from --dump"
echo "ok: the inspector shows the image --dump writes"

# The inspector panel shows its image fitted into the window: cut out of a shot of the whole
# window (UI included), it is the headless render scaled down to the panel's size.
"$bin" view --scene "$scene" --size 1100x500 --frames 2 --inspect ldr --window-shot "$dir/window.png" --validate > "$dir/log" 2>&1 || fail "view --window-shot exited $?"
where=$(sed -n 's/^view: window shot .*; inspector image ldr at \([0-9]*\),\([0-9]*\) \([0-9]*\)x\([0-9]*\)$/\3x\4+\1+\2/p' "$dir/log")
[ -n "$where" ] || fail "view did not say where the inspector's image lies"
"$bin" view --scene "$scene" --size 1100x500 --frames 2 --window-shot "$dir/no_panel.png" --validate > "$dir/log" 2>&1 || fail "view --window-shot exited $?"
# Without a screenshot or the inspector the output reaches the window by a blit on the device, with
# no read-back.
grep -q "goes to the window by a blit on the device" "$dir/log" || fail "the device blit is not used: $(head -3 "$dir/log")"
"$bin" render --scene "$scene" --size 1100x500 --out "$dir/full.png" 2> /dev/null
oiiotool "$dir/window.png" --cut "$where" -o "$dir/panel.png"
oiiotool "$dir/full.png" --resize "${where%%+*}" -o "$dir/expected_panel.png"
"$bin" compare "$dir/panel.png" "$dir/expected_panel.png" --max-l1 0.03 > "$dir/compare" 2>&1 || fail "the inspector panel does not show the image: $(cat "$dir/compare")"
# The same place in a shot without the inspector shows something else (the control must differ).
oiiotool "$dir/no_panel.png" --cut "$where" -o "$dir/no_panel_cut.png"
if "$bin" compare "$dir/no_panel_cut.png" "$dir/expected_panel.png" --max-l1 0.03 > /dev/null 2>&1; then fail "the check cannot tell a panel from none"; fi
echo "ok: the inspector panel shows the image, fitted ($where), in a shot of the whole window"
# Right of the main panel the blitted window shows the headless render exactly.
oiiotool "$dir/no_panel.png" --cut 600x400+460+50 -o "$dir/window_cut.png"
oiiotool "$dir/full.png" --cut 600x400+460+50 -o "$dir/full_cut.png"
"$bin" compare "$dir/window_cut.png" "$dir/full_cut.png" --max-l1 0.001 > "$dir/compare" 2>&1 || fail "the blitted output differs: $(cat "$dir/compare")"
echo "ok: the output blitted into the window is the headless render"

# 2. Left still, the progressive graph takes its while_still values (exact ray-query photons) and goes
# on drawing while its mean converges: the fourth still frame is the headless render of four
# accumulated exact frames, and not the image-space mean's (the control). Moving, the values stay
# as set. Without a frame budget (--budget 0): on a machine slow enough (the sanitizer build under
# load) the default budget takes the next, cheaper, slice level, whose frames differ.
progressive="$src/graphs/caustics_progressive.json"
"$bin" view --scene "$scene" --graph "$progressive" --size 160x90 --frames 4 --still-after 0 --budget 0 --screenshot "$dir/still.png" --stats "$dir/still.json" --validate > "$dir/log" 2>&1 || fail "view of the progressive graph exited $?"
"$bin" render --scene "$scene" --graph "$progressive" --size 160x90 --set distance=ray_query --set slice_side=2 --accumulate 4 --out "$dir/exact4.png" 2> /dev/null
"$bin" render --scene "$scene" --graph "$progressive" --size 160x90 --accumulate 4 --moving --out "$dir/image4.png" 2> /dev/null
"$bin" compare "$dir/still.png" "$dir/exact4.png" --max-l1 0.001 > "$dir/compare" 2>&1 || fail "the still view is not four accumulated exact frames: $(cat "$dir/compare")"
if "$bin" compare "$dir/still.png" "$dir/image4.png" --max-l1 0.001 > /dev/null 2>&1; then fail "the check cannot tell exact photons from image-space ones"; fi
python3 - "$dir/still.json" <<'PY' || fail "the still frames do not take the while_still values, or do not converge"
import json, sys
still = json.load(open(sys.argv[1]))["frames"]
assert all(f["still"] and f["converging"] and not f["moving"] for f in still), still
PY
# A parameter set on the command line stays as set at rest, as one set in the panel does (a choice:
# the search, not the while_still ray queries; the other while_still value, slice_side 2, holds).
"$bin" view --scene "$scene" --graph "$progressive" --size 160x90 --frames 4 --still-after 0 --budget 0 --set distance=search --screenshot "$dir/still_search.png" --validate > "$dir/log" 2>&1 || fail "view --set distance=search exited $?: $(cat "$dir/log")"
"$bin" render --scene "$scene" --graph "$progressive" --size 160x90 --set distance=search --set slice_side=2 --accumulate 4 --out "$dir/search4.png" 2> /dev/null
"$bin" compare "$dir/still_search.png" "$dir/search4.png" --max-l1 0.001 > "$dir/compare" 2>&1 || fail "view --set distance=search is not four accumulated search frames: $(cat "$dir/compare")"
if "$bin" compare "$dir/still_search.png" "$dir/exact4.png" --max-l1 0.001 > /dev/null 2>&1; then fail "the check cannot tell the search from ray queries"; fi
echo "ok: at rest the progressive graph's still frames are the headless accumulation of its while_still values"
