#!/usr/bin/env python3
"""Writes the glass balls of the glTF interface extensions (docs/gltf.md, "The interface"): each a
smooth UV sphere (radius 1, 64 x 32 segments, at the origin) whose one material is glass
(KHR_materials_transmission, _volume, _ior 1.5) with interface layers:
  clearcoat_ball.gltf      KHR_materials_clearcoat, a full coat (clearcoatFactor 1)
  specular_ball.gltf       KHR_materials_specular, a reddish F0 (specularColorFactor 2.5, 1, 0.4)
  iridescent_ball.gltf     KHR_materials_iridescence, a film of index 2.0 and 380 nm (iridescenceFactor 1)
  coated_rough_ball.gltf   a rough base (roughnessFactor 0.4) under a smooth full clear coat
Beside the first three, in tests/data/layered, a scene (NAME.json) that puts the ball where the
ball lens of scenes/sphere_plane.json stands (the tests' and the gallery's); scenes/stability uses
the film and the coat over the rough base. Everything is embedded.
Run from this folder: python3 make_layered_balls.py"""
import base64, json, re, struct

from uv_sphere import sphere


def ball(name, extensions, roughness=0.0, scene=True):
    positions, _, indices = sphere()
    blob = b"".join(struct.pack("<3f", *p) for p in positions)  # positions, and the same as normals
    blob += b"".join(struct.pack("<H", i) for i in indices)
    vertex_bytes = 12 * len(positions)
    used = ["KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior"] + sorted(extensions)
    material_extensions = {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                           "KHR_materials_volume": {"thicknessFactor": 2.0},
                           "KHR_materials_ior": {"ior": 1.5}}
    material_extensions.update(extensions)
    gltf = {
        "asset": {"version": "2.0", "generator": "caustica tests/data/layered/make_layered.py"},
        "extensionsUsed": used,
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": name}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"name": name, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0,
                                                                                          "roughnessFactor": roughness},
                       "extensions": material_extensions}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": vertex_bytes},
                        {"buffer": 0, "byteOffset": vertex_bytes, "byteLength": 2 * len(indices)}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }
    with open(name + ".gltf", "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")
    if not scene:
        return
    scene = json.load(open("../sphere_plane.json"))
    scene["name"] = name
    scene["description"] = "The ball lens of scenes/sphere_plane.json, its glass from scenes/materials/" + name + ".gltf: " + DESCRIPTIONS[name]
    scene["objects"][-1] = {"name": "ball", "mesh": "../../../scenes/materials/" + name + ".gltf", "transform": {"translate": [0, 1.5, 0]}}
    with open("../../tests/data/layered/" + name + ".json", "w") as f:
        text = json.dumps(scene, indent=2)
        # short lists of numbers on one line, as the bundled scenes write them
        text = re.sub(r"\[\s*([-0-9.,\s]+?)\s*\]", lambda m: "[" + ", ".join(m.group(1).split()).replace(",,", ",") + "]", text)
        f.write(text + "\n")


DESCRIPTIONS = {
    "clearcoat_ball": "a full clear coat (KHR_materials_clearcoat).",
    "specular_ball": "a reddish specular F0 (KHR_materials_specular), which leaves the caustic cyan.",
    "iridescent_ball": "a thin film of index 2.0, 380 nm thick (KHR_materials_iridescence), which colours the caustic.",
}
ball("clearcoat_ball", {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.0}})
ball("specular_ball", {"KHR_materials_specular": {"specularFactor": 1.0, "specularColorFactor": [2.5, 1.0, 0.4]}})
ball("iridescent_ball", {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceIor": 2.0,
                                                       "iridescenceThicknessMaximum": 380.0}})
ball("coated_rough_ball", {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.0}}, roughness=0.4, scene=False)
