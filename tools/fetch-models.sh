#!/usr/bin/env bash
# Puts the scanned meshes that bundled scenes use where the scenes expect them. The Stanford bunny
# is read straight from glmark2-data; the armadillo and the dragon sit inside libcgal-demo's data
# tarball and are extracted into scenes/models/ (not in git). Idempotent.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
tarball=/usr/share/doc/libcgal-dev/data.tar.gz
out="$root/scenes/models"
mkdir -p "$out"
for mesh in armadillo.off ChineseDragon-10kv.off; do
  [ -s "$out/$mesh" ] && continue
  [ -f "$tarball" ] || { echo "fetch-models: $tarball is missing (apt-get install libcgal-demo)" >&2; exit 1; }
  tmp="$(mktemp -d)"
  tar xzf "$tarball" -C "$tmp" "data/meshes/$mesh"
  mv "$tmp/data/meshes/$mesh" "$out/$mesh.partial" && mv "$out/$mesh.partial" "$out/$mesh"
  rm -rf "$tmp"
  echo "fetch-models: extracted $mesh"
done
[ -f /usr/share/glmark2/models/bunny.obj ] || { echo "fetch-models: glmark2-data's bunny.obj is missing" >&2; exit 1; }
