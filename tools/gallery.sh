#!/usr/bin/env bash
# The docs/gallery pictures and table: each asset rendered by the default graph and by the
# ray-query caustic graph, beside the Embree reference picture lit by a photon-reference caustic
# map, and each graph's caustic map (and the ray-query graph's with distance=material) against
# that map (energy ratio, relative L1), and each graph's picture against the reference picture
# (relative L1 of luminance, matched blur 1.5 pixels).
#   tools/gallery.sh [CAUSTICA] [SAMPLES_DIR] [PHOTONS] [ONLY]
# CAUSTICA defaults to build/release/caustica, SAMPLES_DIR to $CAUSTICA_GLTF_SAMPLES, a folder
# of KhronosGroup/glTF-Sample-Assets models (the Khronos transmission samples; skipped when absent), PHOTONS to 2e7; ONLY, a comma-separated list of asset
# names, renders those alone. Writes docs/gallery/*.png and prints the table that docs/gallery.md
# quotes.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-build/release/caustica}")
samples=${2:-${CAUSTICA_GLTF_SAMPLES:-}}
photons=${3:-2e7}
only=${4:-}
out=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"

assets=()
for sample in TransmissionTest AttenuationTest TransmissionRoughnessTest; do
  [ -f "$samples/$sample.glb" ] && assets+=("$sample|$samples/$sample.glb")
done
assets+=("thin_panes|scenes/thin_panes.json" "sphere_sun|scenes/sphere_sun.json" "glass_cube|tests/data/gltf/cube_camera_spot.gltf"
  "dragon|scenes/dragon.json" "rainbow_lens|scenes/rainbow_lens.json" "mask_over_lens|tests/data/mask_over_lens.json"
  "tinted_pane|tests/data/gltf/tinted_pane.gltf" "blend_pane|tests/data/gltf/blend_pane.gltf" "rough_pane|tests/data/gltf/rough_pane.gltf"
  "clearcoat_ball|tests/data/layered/clearcoat_ball.json" "specular_ball|tests/data/layered/specular_ball.json"
  "iridescent_ball|tests/data/layered/iridescent_ball.json")

energy() {  # A B -> "energy_ratio relative_l1"
  "$bin" compare "$1" "$2" --json | python3 -c 'import json, sys; d = json.load(sys.stdin); print("%.3f %.3f" % (d["energy_ratio"], d["relative_l1"]))'
}

{
  echo "| asset | default graph: energy, relative L1 | caustics_raytraced: energy, relative L1 | caustics_raytraced, distance=material: energy, relative L1 | reference: entering flux that lands |"
  echo "|---|---|---|---|---|"
} > "$work/table.md"
for entry in "${assets[@]}"; do
  name=${entry%%|*}
  scene=${entry#*|}
  [ -n "$only" ] && [[ ",$only," != *",$name,"* ]] && continue
  echo "== $name ($scene)" >&2
  "$bin" render --scene "$scene" --size 640x360 --out "$out/$name.png" --out "$work/$name.default.picture.exr" \
    --dump "caustics=$work/$name.default.exr" >&2
  "$bin" render --scene "$scene" --graph graphs/caustics_raytraced.json --size 640x360 --out "$out/${name}_raytraced.png" \
    --out "$work/$name.raytraced.picture.exr" --dump "caustics=$work/$name.raytraced.exr" >&2
  "$bin" render --scene "$scene" --graph graphs/caustics_raytraced.json --set distance=material --size 640x360 --out "$work/material.png" \
    --dump "caustics=$work/$name.material.exr" >&2
  "$bin" reference --scene "$scene" --photons "$photons" --out "$work/$name.map.exr" > "$work/$name.photons.txt"
  "$bin" reference --scene "$scene" --size 640x360 --caustics "$work/$name.map.exr" --out "$out/${name}_reference.png" >&2
  "$bin" reference --scene "$scene" --size 640x360 --caustics "$work/$name.map.exr" --out "$work/$name.reference.picture.exr" >&2
  landed=$(grep -o 'landed in the map [^)]*)' "$work/$name.photons.txt" | sed 's/.*(//; s/)//' || true)
  read -r de dl <<< "$(energy "$work/$name.default.exr" "$work/$name.map.exr")"
  read -r re rl <<< "$(energy "$work/$name.raytraced.exr" "$work/$name.map.exr")"
  read -r me ml <<< "$(energy "$work/$name.material.exr" "$work/$name.map.exr")"
  echo "| $name | $de, $dl | $re, $rl | $me, $ml | ${landed:-?} |" >> "$work/table.md"
  read -r _ dp <<< "$(energy "$work/$name.default.picture.exr" "$work/$name.reference.picture.exr")"
  read -r _ rp <<< "$(energy "$work/$name.raytraced.picture.exr" "$work/$name.reference.picture.exr")"
  echo "| $name | $dp | $rp |" >> "$work/pictures.md"
done
cat "$work/table.md"
echo
echo "| asset | picture, default graph: relative L1 | picture, caustics_raytraced: relative L1 |"
echo "|---|---|---|"
cat "$work/pictures.md"
