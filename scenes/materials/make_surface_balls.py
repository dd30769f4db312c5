#!/usr/bin/env python3
"""Writes the opaque surfaces of glTF's surface extensions (docs/gltf.md, "Opaque surfaces"):
  sheen_ball.gltf         a dark red cloth-like ball (roughness 0.7) under a pale sheen
                          (KHR_materials_sheen, sheenColorFactor 1, 0.85, 0.7, sheenRoughnessFactor 0.3)
  anisotropic_ball.gltf   a brushed metal ball (roughness 0.35), its highlight stretched along the lines
                          of latitude (KHR_materials_anisotropy, strength 0.9; TANGENT along them)
  translucent_leaf.gltf   a green double-sided leaf, 2 x 2, that passes 70% of its diffuse light to its
                          other side, yellow-green (KHR_materials_diffuse_transmission)
  coated_ball.gltf        a rough red ball under a smooth clear coat (KHR_materials_clearcoat)
  tinted_specular_ball.gltf  a dark ball whose dielectric F0 is tinted orange and raised by an index
                          of 1.8 (KHR_materials_specular, KHR_materials_ior)
  film_ball.gltf          a dark ball under a thin film of index 1.4, 350 nm thick (KHR_materials_iridescence)
Each ball is a UV sphere of radius 1 (64 x 32 segments) at the origin; the leaf stands in the xy
plane facing +z. Beside each, in tests/data/surfaces, a scene (NAME.json) on the floor of
scenes/sphere_plane.json: the balls lit from above the camera's side, the leaf from behind it.
Everything is embedded. Run from this folder: python3 make_surface_balls.py"""
import base64, json, re, struct

from uv_sphere import sphere


def ball():
    positions, tangents, indices = sphere()
    return positions, None, tangents, indices


def leaf():
    positions = [(-1.0, -1.0, 0.0), (1.0, -1.0, 0.0), (1.0, 1.0, 0.0), (-1.0, 1.0, 0.0)]
    return positions, [(0.0, 0.0, 1.0)] * 4, None, [0, 1, 2, 0, 2, 3]


def write_gltf(name, geometry, material, extension):
    positions, normals, tangents, indices = geometry
    normals = normals or positions  # a unit sphere's normals are its positions
    blob = b"".join(struct.pack("<3f", *p) for p in positions) + b"".join(struct.pack("<3f", *n) for n in normals)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * len(positions)},
             {"buffer": 0, "byteOffset": 12 * len(positions), "byteLength": 12 * len(positions)}]
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi},
                 {"bufferView": 1, "componentType": 5126, "count": len(positions), "type": "VEC3"}]
    attributes = {"POSITION": 0, "NORMAL": 1}
    if tangents:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": 16 * len(tangents)})
        blob += b"".join(struct.pack("<4f", *t) for t in tangents)
        accessors.append({"bufferView": 2, "componentType": 5126, "count": len(tangents), "type": "VEC4"})
        attributes["TANGENT"] = 2
    views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": 2 * len(indices)})
    blob += b"".join(struct.pack("<H", i) for i in indices)
    accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
    material = dict(material, name=name, extensions=extension)
    gltf = {
        "asset": {"version": "2.0", "generator": "caustica scenes/materials/make_surface_balls.py"},
        "extensionsUsed": sorted(extension),
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": name}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": len(accessors) - 1, "material": 0}]}],
        "materials": [material],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }
    with open(name + ".gltf", "w") as f:
        json.dump(gltf, f, separators=(",", ":"))
        f.write("\n")


def write_scene(name, description, light, translate):
    scene = json.load(open("../sphere_plane.json"))
    scene["name"] = name
    scene["description"] = description
    scene["lights"] = [light]
    scene["objects"][-1] = {"name": name, "mesh": "../../../scenes/materials/" + name + ".gltf", "transform": {"translate": translate}}
    with open("../../tests/data/surfaces/" + name + ".json", "w") as f:
        text = json.dumps(scene, indent=2)
        text = re.sub(r"\[\s*([-0-9.,\s]+?)\s*\]", lambda m: "[" + ", ".join(m.group(1).split()).replace(",,", ",") + "]", text)
        f.write(text + "\n")


FRONT_LIGHT = {"type": "spot", "position": [2.5, 6.0, 5.0], "target": [0.0, 1.5, 0.0], "fov": 30, "intensity": 250}
BACK_LIGHT = {"type": "spot", "position": [0.5, 4.0, -5.0], "target": [0.0, 1.5, 0.0], "fov": 35, "intensity": 250}

write_gltf("sheen_ball", ball(),
           {"pbrMetallicRoughness": {"baseColorFactor": [0.25, 0.04, 0.06, 1], "metallicFactor": 0.0, "roughnessFactor": 0.7}},
           {"KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.85, 0.7], "sheenRoughnessFactor": 0.3}})
write_scene("sheen_ball", "A cloth-like ball with a pale sheen (scenes/materials/sheen_ball.gltf, KHR_materials_sheen) on the floor of "
            "scenes/sphere_plane.json, lit from above the camera's side.", FRONT_LIGHT, [0, 1.5, 0])
write_gltf("anisotropic_ball", ball(),
           {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 1.0, "roughnessFactor": 0.35}},
           {"KHR_materials_anisotropy": {"anisotropyStrength": 0.9, "anisotropyRotation": 0.0}})
write_scene("anisotropic_ball", "A brushed metal ball whose highlight stretches along its lines of latitude (scenes/materials/"
            "anisotropic_ball.gltf, KHR_materials_anisotropy) on the floor of scenes/sphere_plane.json.", FRONT_LIGHT, [0, 1.5, 0])
write_gltf("translucent_leaf", leaf(),
           {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.45, 0.1, 1], "metallicFactor": 0.0, "roughnessFactor": 0.8},
            "doubleSided": True},
           {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.7,
                                                   "diffuseTransmissionColorFactor": [0.7, 1.0, 0.2]}})
write_scene("translucent_leaf", "A leaf that passes 70% of its diffuse light through (scenes/materials/translucent_leaf.gltf, "
            "KHR_materials_diffuse_transmission), lit from behind: the camera sees the light it lets through.", BACK_LIGHT, [0, 1.5, 0])
write_gltf("coated_ball", ball(),
           {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.03, 0.02, 1], "metallicFactor": 0.0, "roughnessFactor": 0.6}},
           {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.08}})
write_scene("coated_ball", "A rough red ball under a smooth clear coat, like car paint (scenes/materials/coated_ball.gltf, "
            "KHR_materials_clearcoat) on the floor of scenes/sphere_plane.json.", FRONT_LIGHT, [0, 1.5, 0])
write_gltf("tinted_specular_ball", ball(),
           {"pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.06, 1], "metallicFactor": 0.0, "roughnessFactor": 0.3}},
           {"KHR_materials_specular": {"specularFactor": 1.0, "specularColorFactor": [1.0, 0.55, 0.15]},
            "KHR_materials_ior": {"ior": 1.8}})
write_scene("tinted_specular_ball", "A dark ball whose dielectric reflection is tinted orange and raised by its index (scenes/"
            "materials/tinted_specular_ball.gltf, KHR_materials_specular and KHR_materials_ior) on the floor of scenes/sphere_plane.json.",
            FRONT_LIGHT, [0, 1.5, 0])
write_gltf("film_ball", ball(),
           {"pbrMetallicRoughness": {"baseColorFactor": [0.03, 0.03, 0.03, 1], "metallicFactor": 0.0, "roughnessFactor": 0.25}},
           {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceIor": 1.4, "iridescenceThicknessMaximum": 350}})
write_scene("film_ball", "A dark ball under a thin film 350 nm thick, like oil on water (scenes/materials/film_ball.gltf, "
            "KHR_materials_iridescence) on the floor of scenes/sphere_plane.json.", FRONT_LIGHT, [0, 1.5, 0])
