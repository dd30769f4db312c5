#!/usr/bin/env bash
# Regenerates the compressed glTF test assets from scenes/models/ChineseDragon-10kv.off with the
# encoders the extensions' authors ship (Debian packages draco and gltfpack; the tests only need
# the decoders): dragon_draco.glb (KHR_draco_mesh_compression, positions quantized to 16 bits),
# dragon_meshopt.glb (EXT_meshopt_compression with KHR_mesh_quantization, gltfpack -c), and the
# lossless dragon_draco_lossless.glb (-qp 0) and dragon_meshopt_lossless.glb (gltfpack -c -noq),
# all from dragon.glb, the uncompressed original it writes first.
# scene_test compares what caustica decodes from them with the OFF file itself; cli_test renders
# the lossless ones to dragon.glb's picture (same glTF material; the OFF file is Lambertian).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$here/../../../scenes/models/ChineseDragon-10kv.off" "$here/dragon.glb" <<'EOF'
import json, struct, sys
words = open(sys.argv[1]).read().split()
assert words[0] == "OFF"
nv, nf = int(words[1]), int(words[2])
at = 4
positions = [float(w) for w in words[at:at + 3 * nv]]
at += 3 * nv
indices = []
for _ in range(nf):
    n = int(words[at])
    face = [int(w) for w in words[at + 1:at + 1 + n]]
    at += 1 + n
    for i in range(1, n - 1):
        indices += [face[0], face[i], face[i + 1]]
pos = struct.pack(f"<{len(positions)}f", *positions)
idx = struct.pack(f"<{len(indices)}I", *indices)
lo = [min(positions[c::3]) for c in range(3)]
hi = [max(positions[c::3]) for c in range(3)]
doc = {
    "asset": {"version": "2.0", "generator": "caustica tests/data/gltf/make_compressed.sh"},
    "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"name": "dragon", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    # caustica's own default albedo, so that the OFF file renders the same picture
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1]}}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": lo, "max": hi},
        {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
                    {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx), "target": 34963}],
    "buffers": [{"byteLength": len(pos) + len(idx)}],
}
text = json.dumps(doc).encode()
text += b" " * (-len(text) % 4)
binary = pos + idx
with open(sys.argv[2], "wb") as f:
    f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary)))
    f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
    f.write(struct.pack("<II", len(binary), 0x004E4942) + binary)
EOF
draco_transcoder -i "$here/dragon.glb" -o "$here/dragon_draco.glb" -qp 16
gltfpack -i "$here/dragon.glb" -o "$here/dragon_meshopt.glb" -c
draco_transcoder -i "$here/dragon.glb" -o "$here/dragon_draco_lossless.glb" -qp 0
gltfpack -i "$here/dragon.glb" -o "$here/dragon_meshopt_lossless.glb" -c -noq
