#!/usr/bin/env python3
"""Writes textured_mask.gltf: a test scene for base colour textures, KHR_texture_transform, a second
texture coordinate set and alpha MASK. A checkered floor (texture 0 through a transform) under a
quad whose coverage is a checker of alpha 0 and 1 (texture 1, TEXCOORD_1, MASK), a spot light
straight above, and a camera. Everything is embedded, so the file stands alone.
Also writes malformed variants for the bad-input tests (bad_texture_*.gltf, bad_occlusion_strength.gltf,
bad_tangent_count.gltf), and textured_surfaces.gltf, rough_pane.gltf, tinted_pane.gltf,
blend_pane.gltf, layered_pane.gltf, textured_extensions.gltf and half_leaf.gltf (below).
Run from this folder: python3 make_textured.py"""
import base64, json, math, struct, zlib


def png(width, height, pixels):  # pixels: rows of (r, g, b, a) bytes
    raw = b"".join(b"\x00" + bytes(v for p in row for v in p) for row in pixels)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def data_uri(mime, data):
    return "data:%s;base64,%s" % (mime, base64.b64encode(data).decode())


floor_colors = [(230, 120, 40, 255), (80, 160, 230, 255)]
floor_png = png(8, 8, [[floor_colors[(x // 2 + y // 2) % 2] for x in range(8)] for y in range(8)])
mask_png = png(4, 4, [[(255, 255, 255, 255 if (x + y) % 2 == 0 else 0) for x in range(4)] for y in range(4)])

# Two quads facing +y: the floor (4 x 4 at y = 0) and the masked quad (1.6 x 1.6 at y = 1).
def quad(half, y):
    return [(-half, y, -half), (half, y, -half), (half, y, half), (-half, y, half)]
positions = quad(2.0, 0.0) + quad(0.8, 1.0)
normals = [(0.0, 1.0, 0.0)] * 8
uv0 = [(0, 0), (1, 0), (1, 1), (0, 1)] * 2
uv1 = [(0, 0), (1, 0), (1, 1), (0, 1)] * 2
indices = [0, 2, 1, 0, 3, 2]  # counter-clockwise seen from +y
blob = b"".join(struct.pack("<3f", *p) for p in positions)
blob += b"".join(struct.pack("<3f", *n) for n in normals)
blob += b"".join(struct.pack("<2f", *t) for t in uv0)
blob += b"".join(struct.pack("<2f", *t) for t in uv1)
blob += b"".join(struct.pack("<H", i) for i in indices)
offsets = {"pos": 0, "nrm": 96, "uv0": 192, "uv1": 256, "idx": 320}

views, accessors = [], []
def view(offset, length):
    views.append({"buffer": 0, "byteOffset": offset, "byteLength": length})
    return len(views) - 1
def accessor(v, offset, count, kind, component=5126, **extra):
    accessors.append(dict({"bufferView": v, "byteOffset": offset, "count": count, "type": kind, "componentType": component}, **extra))
    return len(accessors) - 1
pos_view, nrm_view = view(offsets["pos"], 96), view(offsets["nrm"], 96)
uv0_view, uv1_view, idx_view = view(offsets["uv0"], 64), view(offsets["uv1"], 64), view(offsets["idx"], 12)
def primitive(first, material):
    return {"attributes": {"POSITION": accessor(pos_view, first * 12, 4, "VEC3", min=[-2, 0, -2] if first == 0 else [-0.8, 1, -0.8],
                                                 max=[2, 0, 2] if first == 0 else [0.8, 1, 0.8]),
                           "NORMAL": accessor(nrm_view, first * 12, 4, "VEC3"),
                           "TEXCOORD_0": accessor(uv0_view, first * 8, 4, "VEC2"),
                           "TEXCOORD_1": accessor(uv1_view, first * 8, 4, "VEC2")},
            "indices": accessor(idx_view, 0, 6, "SCALAR", 5123), "material": material}

half = math.radians(-90) / 2
down = [math.sin(half), 0, 0, math.cos(half)]
tilt = math.atan2(3.0, 4.0) / 2
gltf = {
    "asset": {"version": "2.0", "generator": "caustica tests/data/gltf/make_textured.py"},
    "extensionsUsed": ["KHR_texture_transform", "KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 30.0, "spot": {"outerConeAngle": 0.75}}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3]}],
    "nodes": [{"mesh": 0}, {"mesh": 1},
              {"translation": [0, 4, 0], "rotation": down, "extensions": {"KHR_lights_punctual": {"light": 0}}},
              {"camera": 0, "translation": [0, 3, 4], "rotation": [-math.sin(tilt), 0, 0, math.cos(tilt)]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 50}}],
    "meshes": [{"name": "floor", "primitives": [primitive(0, 0)]}, {"name": "mask", "primitives": [primitive(4, 1)]}],
    "materials": [
        {"name": "checkered floor",
         "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
             "offset": [0.25, 0.0], "rotation": 0.3, "scale": [2.0, 2.0]}}}, "metallicFactor": 0.0}},
        {"name": "masked quad", "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1.0], "baseColorTexture": {"index": 1, "texCoord": 1},
                                  "metallicFactor": 0.0}}],
    "textures": [{"sampler": 0, "source": 0}, {"sampler": 0, "source": 1}],
    "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 10497, "wrapT": 10497}],
    "images": [{"uri": data_uri("image/png", floor_png)}, {"uri": data_uri("image/png", mask_png)},
               {"uri": data_uri("image/png", png(1, 1, [[(255, 0, 255, 255)]]))}],
    "buffers": [{"byteLength": len(blob), "uri": data_uri("application/octet-stream", blob)}],
    "bufferViews": views,
    "accessors": accessors,
}
def write(name, content):
    with open(name, "w") as out:
        json.dump(content, out, indent=1)
        out.write("\n")


write("textured_mask.gltf", gltf)
bad = json.loads(json.dumps(gltf))
bad["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 7
write("bad_texture_index.gltf", bad)
bad = json.loads(json.dumps(gltf))
bad["samplers"][0]["wrapS"] = 1234
write("bad_texture_wrap.gltf", bad)
bad = json.loads(json.dumps(gltf))
bad["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 2
write("bad_texture_texcoord.gltf", bad)
bad = json.loads(json.dumps(gltf))
bad["images"][1]["uri"] = data_uri("image/png", b"\x89PNG not really")
write("bad_texture_image.gltf", bad)


# textured_surfaces.gltf: glTF's metallic-roughness model with its textures, a normal map in the
# floor's own TANGENT frame, an occlusion map (bands across the floor that take 0.9 of the sky light), emission
# (KHR_materials_emissive_strength) and a single-sided quad whose back faces the camera.
def build(quads):  # quads: (corners counter-clockwise seen from the front, normal, material[, tangent])
    data, meshes, views2, accessors2 = b"", [], [], []
    for corners, normal, material, *tangent in quads:
        start = len(data)
        data += b"".join(struct.pack("<3f", *c) for c in corners)
        data += b"".join(struct.pack("<3f", *normal) for _ in corners)
        data += b"".join(struct.pack("<2f", *t) for t in [(0, 1), (1, 1), (1, 0), (0, 0)])
        data += b"".join(struct.pack("<H", i) for i in [0, 1, 2, 0, 2, 3])
        data += b"\0" * (-len(data) % 4)
        base = len(views2)
        views2 += [{"buffer": 0, "byteOffset": start, "byteLength": 48}, {"buffer": 0, "byteOffset": start + 48, "byteLength": 48},
                   {"buffer": 0, "byteOffset": start + 96, "byteLength": 32}, {"buffer": 0, "byteOffset": start + 128, "byteLength": 12}]
        lo = [min(c[k] for c in corners) for k in range(3)]
        hi = [max(c[k] for c in corners) for k in range(3)]
        a = len(accessors2)
        accessors2 += [{"bufferView": base, "count": 4, "type": "VEC3", "componentType": 5126, "min": lo, "max": hi},
                       {"bufferView": base + 1, "count": 4, "type": "VEC3", "componentType": 5126},
                       {"bufferView": base + 2, "count": 4, "type": "VEC2", "componentType": 5126},
                       {"bufferView": base + 3, "count": 6, "type": "SCALAR", "componentType": 5123}]
        attributes = {"POSITION": a, "NORMAL": a + 1, "TEXCOORD_0": a + 2}
        if tangent:
            views2.append({"buffer": 0, "byteOffset": len(data), "byteLength": 64})
            data += b"".join(struct.pack("<4f", *tangent[0]) for _ in corners)
            attributes["TANGENT"] = len(accessors2)
            accessors2.append({"bufferView": len(views2) - 1, "count": 4, "type": "VEC4", "componentType": 5126})
        meshes.append({"primitives": [{"attributes": attributes, "indices": a + 3, "material": material}]})
    return data, meshes, views2, accessors2


def encode_normal(x, y):
    z = math.sqrt(max(0.0, 1 - x * x - y * y))
    return tuple(int(round((v * 0.5 + 0.5) * 255)) for v in (x, y, z)) + (255,)


ridges = png(16, 16, [[encode_normal(0.7 * math.sin(2 * math.pi * x / 4), 0.3 * math.cos(2 * math.pi * y / 8)) for x in range(16)]
                      for y in range(16)])
metal_rough = png(8, 8, [[(0, 70, 255, 255) if (x // 2 + y // 2) % 2 == 0 else (0, 220, 0, 255) for x in range(8)] for y in range(8)])
glow = png(8, 8, [[(255, 255, 255, 255) if x % 4 < 2 else (40, 40, 40, 255) for x in range(8)] for y in range(8)])
occluded_bands = png(8, 8, [[(255, 0, 0, 255) if y % 4 < 2 else (0, 0, 0, 255) for x in range(8)] for y in range(8)])
surfaces_blob, surface_meshes, surface_views, surface_accessors = build([
    # floor, facing up, with a TANGENT frame turned a quarter from its texture coordinates' and mirrored
    ([(-2, 0, 2), (2, 0, 2), (2, 0, -2), (-2, 0, -2)], (0, 1, 0), 0, (0, 0, 1, -1)),
    ([(-1, 0.3, -1.5), (1, 0.3, -1.5), (1, 1.3, -1.5), (-1, 1.3, -1.5)], (0, 0, 1), 1),  # emissive panel, facing the camera
    ([(0.6, 0.6, 1.0), (-0.6, 0.6, 1.0), (-0.6, 1.8, 1.0), (0.6, 1.8, 1.0)], (0, 0, -1), 2),  # single-sided, facing away
])
surfaces = {
    "asset": {"version": "2.0", "generator": "caustica tests/data/gltf/make_textured.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 40.0, "spot": {"outerConeAngle": 0.8}}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
    "nodes": [{"mesh": 0}, {"mesh": 1}, {"mesh": 2},
              {"translation": [1.0, 4, 1.0], "rotation": down, "extensions": {"KHR_lights_punctual": {"light": 0}}},
              {"camera": 0, "translation": [0, 3, 4], "rotation": [-math.sin(tilt), 0, 0, math.cos(tilt)]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 50}}],
    "meshes": surface_meshes,
    "materials": [
        {"name": "bumped metal and plastic",
         "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1.0], "metallicRoughnessTexture": {"index": 0}},
         "normalTexture": {"index": 1, "scale": 1.0}, "occlusionTexture": {"index": 3, "strength": 0.9}},
        {"name": "glowing panel", "emissiveFactor": [1.0, 0.8, 0.5], "emissiveTexture": {"index": 2},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2.0}},
         "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1.0], "metallicFactor": 0.0}},
        {"name": "single-sided red", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0}}],
    "textures": [{"sampler": 0, "source": 0}, {"sampler": 0, "source": 1}, {"sampler": 0, "source": 2}, {"sampler": 0, "source": 3}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
    "images": [{"uri": data_uri("image/png", metal_rough)}, {"uri": data_uri("image/png", ridges)}, {"uri": data_uri("image/png", glow)},
               {"uri": data_uri("image/png", occluded_bands)}],
    "buffers": [{"byteLength": len(surfaces_blob), "uri": data_uri("application/octet-stream", surfaces_blob)}],
    "bufferViews": surface_views,
    "accessors": surface_accessors,
}
write("textured_surfaces.gltf", surfaces)
bad = json.loads(json.dumps(surfaces))
bad["materials"][0]["occlusionTexture"]["strength"] = 1.5
write("bad_occlusion_strength.gltf", bad)
bad = json.loads(json.dumps(surfaces))
bad["accessors"][bad["meshes"][0]["primitives"][0]["attributes"]["TANGENT"]]["count"] = 3
write("bad_tangent_count.gltf", bad)


# rough_pane.gltf: a thin transmissive pane (KHR_materials_transmission without a volume) over a
# floor, under a spot light straight above. Its metallic-roughness texture makes the half at -x
# smooth (green 0) and the half at +x fully rough (green 255, roughnessFactor 1): light passes the
# smooth half unbent and is scattered by the rough half, so only that half's light spills past the
# pane's shadow on the floor.
pane_blob, pane_meshes, pane_views, pane_accessors = build([
    ([(-2, 0, 2), (2, 0, 2), (2, 0, -2), (-2, 0, -2)], (0, 1, 0), 0),              # floor
    ([(-0.8, 1, 0.8), (0.8, 1, 0.8), (0.8, 1, -0.8), (-0.8, 1, -0.8)], (0, 1, 0), 1),  # pane: u from -x to +x
])
pane = {
    "asset": {"version": "2.0", "generator": "caustica tests/data/gltf/make_textured.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 30.0, "spot": {"outerConeAngle": 0.75}}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3]}],
    "nodes": [{"mesh": 0}, {"mesh": 1},
              {"translation": [0, 4, 0], "rotation": down, "extensions": {"KHR_lights_punctual": {"light": 0}}},
              {"camera": 0, "translation": [0, 3, 4], "rotation": [-math.sin(tilt), 0, 0, math.cos(tilt)]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 50}}],
    "meshes": pane_meshes,
    "materials": [
        {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0}},
        {"name": "half-rough pane", "doubleSided": True,
         "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0, "metallicRoughnessTexture": {"index": 0}},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}],
    "textures": [{"sampler": 0, "source": 0}],
    "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}],
    "images": [{"uri": data_uri("image/png", png(2, 1, [[(0, 0, 0, 255), (0, 255, 0, 255)]]))}],
    "buffers": [{"byteLength": len(pane_blob), "uri": data_uri("application/octet-stream", pane_blob)}],
    "bufferViews": pane_views,
    "accessors": pane_accessors,
}
write("rough_pane.gltf", pane)


# tinted_pane.gltf: the same smooth thin pane, whose base colour texture is red on its -x half and
# blue on its +x half, and whose transmission texture lets all the light through the -x half and a
# quarter of it through the +x half: light passes unbent, so the floor under each half gets that
# half's colour and share (one tint and transmission for the whole pane would give both halves
# the same).
tinted = json.loads(json.dumps(pane))
tinted["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_transmission"]
tinted["materials"][1] = {
    "name": "two-tone pane", "doubleSided": True,
    "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.0},
    "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0, "transmissionTexture": {"index": 1}}}}
tinted["textures"] = [{"sampler": 0, "source": 0}, {"sampler": 0, "source": 1}]
tinted["images"] = [{"uri": data_uri("image/png", png(2, 1, [[(255, 40, 40, 255), (40, 40, 255, 255)]]))},
                    {"uri": data_uri("image/png", png(2, 1, [[(255, 0, 0, 255), (64, 0, 0, 255)]]))}]
write("tinted_pane.gltf", tinted)


# blend_pane.gltf: the same pane as alphaMode BLEND (no transmission extension), red and a quarter
# covered on its -x half, blue and three quarters covered on its +x half: drawn as a thin wall that
# passes the uncovered share, it lets three quarters of the light through the -x half, red, and a
# quarter through the +x half, blue (one coverage for the whole pane, its mean, would pass half
# through both).
blended = json.loads(json.dumps(pane))
blended["extensionsUsed"] = ["KHR_lights_punctual"]
blended["materials"][1] = {
    "name": "two-tone blended pane", "doubleSided": True, "alphaMode": "BLEND",
    "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.0}}
blended["textures"] = [{"sampler": 0, "source": 0}]
blended["images"] = [{"uri": data_uri("image/png", png(2, 1, [[(255, 40, 40, 64), (40, 40, 255, 191)]]))}]
write("blend_pane.gltf", blended)


# texture_transform.gltf: KHR_texture_transform's own example (offset [0, 1], rotation pi/2, scale
# [0.5, 0.5]: "only the lower left quadrant of the source image, rotated clockwise 90 degrees") on a
# 4 x 4 texture whose texel (x, y) is (40 + 60 x, 40 + 60 y, 10), sampled NEAREST with REPEAT, on
# the floor of the rough pane's scene; a second material takes offset [0.25, 0] and scale [2, 2]
# without rotation. scene_test checks the texels that chosen texture coordinates reach against
# values worked out by hand from the extension's definition.
transformed = json.loads(json.dumps(pane))
transformed["extensionsUsed"] = ["KHR_lights_punctual", "KHR_texture_transform"]
transformed["materials"] = [
    {"name": "the extension's example",
     "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
         "offset": [0, 1], "rotation": math.pi / 2, "scale": [0.5, 0.5]}}}}},
    {"name": "offset and scale",
     "pbrMetallicRoughness": {"metallicFactor": 0.0, "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
         "offset": [0.25, 0], "scale": [2, 2]}}}}}]
transformed["textures"] = [{"sampler": 0, "source": 0}]
transformed["samplers"] = [{"magFilter": 9728, "minFilter": 9728, "wrapS": 10497, "wrapT": 10497}]
transformed["images"] = [{"uri": data_uri("image/png", png(4, 4, [[(40 + 60 * x, 40 + 60 * y, 10, 255) for x in range(4)] for y in range(4)]))}]
write("texture_transform.gltf", transformed)


# layered_pane.gltf: the same smooth thin pane with glTF's interface layers textured, every layer
# from one 2 x 1 image whose -x texel is (255, 0, 255, 255) and +x texel (0, 255, 0, 0): on the -x
# half KHR_materials_specular's weight is 1 (alpha) and its colour (25, 0, 1) x F0, so that red is
# reflected whole and green not at all; a clear coat of 0.6, a film of 0.7 at 200 nm. On the +x
# half the specular weight is 0 and nothing else is on it but a coat roughness of 0.3 and the
# thickest film (500 nm) at weight 0: all the light passes. Read per texel, the floor under the
# -x half gets no red and the +x half white; the textures' means would give both halves the same.
layered = json.loads(json.dumps(pane))
layered["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_specular",
                             "KHR_materials_clearcoat", "KHR_materials_iridescence"]
layered["materials"][1] = {
    "name": "two-layer pane", "doubleSided": True,
    "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
    "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                   "KHR_materials_specular": {"specularFactor": 1.0, "specularTexture": {"index": 0},
                                              "specularColorFactor": [25.0, 1.0, 1.0], "specularColorTexture": {"index": 0}},
                   "KHR_materials_clearcoat": {"clearcoatFactor": 0.6, "clearcoatTexture": {"index": 0},
                                               "clearcoatRoughnessFactor": 0.3, "clearcoatRoughnessTexture": {"index": 0}},
                   "KHR_materials_iridescence": {"iridescenceFactor": 0.7, "iridescenceTexture": {"index": 0},
                                                 "iridescenceThicknessMinimum": 200.0, "iridescenceThicknessMaximum": 500.0,
                                                 "iridescenceThicknessTexture": {"index": 0}}}}
layered["textures"] = [{"sampler": 0, "source": 0}]
layered["images"] = [{"uri": data_uri("image/png", png(2, 1, [[(255, 0, 255, 255), (0, 255, 0, 0)]]))}]
write("layered_pane.gltf", layered)


# textured_extensions.gltf: the extensions on opaque surfaces with their textures, read per texel
# (docs/gltf.md, "Opaque surfaces"). Four 1 x 1 floor quads around the mirror point of a spot light
# at (0, 3, -4) and the camera at (0, 3, 4): a sheen whose colour and roughness a checker sets; a
# clear coat that stripes switch on and off, rough and smooth, over a ridged normal map of its own;
# KHR_materials_specular's weight and colour from the checker (index 1.8); a thin film that the
# stripes switch on and off, thin and thick. A panel beside them, lit from behind, passes the
# checker's share and colour of its diffuse light (KHR_materials_diffuse_transmission). The
# checker's squares are (255, 160, 60, 255) and (60, 140, 255, 70); the stripes (255, 40, 255, 255)
# and (30, 200, 60, 255): red the coat's and the film's weight, green their roughness and thickness.
checker = png(8, 8, [[(255, 160, 60, 255) if (x // 2 + y // 2) % 2 == 0 else (60, 140, 255, 70) for x in range(8)] for y in range(8)])
stripes = png(8, 8, [[(255, 40, 255, 255) if x % 4 < 2 else (30, 200, 60, 255) for x in range(8)] for y in range(8)])
extension_quads = [
    ([(-1, 0, 0), (0, 0, 0), (0, 0, -1), (-1, 0, -1)], (0, 1, 0), 0),
    ([(0, 0, 0), (1, 0, 0), (1, 0, -1), (0, 0, -1)], (0, 1, 0), 1),
    ([(-1, 0, 1), (0, 0, 1), (0, 0, 0), (-1, 0, 0)], (0, 1, 0), 2),
    ([(0, 0, 1), (1, 0, 1), (1, 0, 0), (0, 0, 0)], (0, 1, 0), 3),
    ([(1.5, 0, -1.5), (2.5, 0, -1.5), (2.5, 1.2, -1.5), (1.5, 1.2, -1.5)], (0, 0, 1), 4),
]
extensions_blob, extension_meshes, extension_views, extension_accessors = build(extension_quads)
base = {"baseColorFactor": [0.3, 0.05, 0.05, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6}
aim = math.atan2(-0.6, -0.8) / 2  # the spot's -z turned to (0, -0.6, 0.8), toward the origin
extensions_gltf = {
    "asset": {"version": "2.0", "generator": "caustica tests/data/gltf/make_textured.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_sheen", "KHR_materials_clearcoat", "KHR_materials_specular",
                       "KHR_materials_ior", "KHR_materials_iridescence", "KHR_materials_diffuse_transmission"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 60.0, "spot": {"outerConeAngle": 0.8}}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3, 4, 5, 6]}],
    "nodes": [{"mesh": 0}, {"mesh": 1}, {"mesh": 2}, {"mesh": 3}, {"mesh": 4},
              {"translation": [0, 3, -4], "rotation": [math.sin(aim), 0, 0, math.cos(aim)],
               "extensions": {"KHR_lights_punctual": {"light": 0}}},
              {"camera": 0, "translation": [0, 3, 4], "rotation": [-math.sin(tilt), 0, 0, math.cos(tilt)]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.05, "zfar": 50}}],
    "meshes": extension_meshes,
    "materials": [
        {"name": "textured sheen", "pbrMetallicRoughness": base,
         "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.9, 0.8], "sheenColorTexture": {"index": 0},
                                                "sheenRoughnessFactor": 0.9, "sheenRoughnessTexture": {"index": 0}}}},
        {"name": "textured coat", "pbrMetallicRoughness": base,
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatTexture": {"index": 1},
                                                    "clearcoatRoughnessFactor": 0.5, "clearcoatRoughnessTexture": {"index": 1},
                                                    "clearcoatNormalTexture": {"index": 2, "scale": 0.8}}}},
        {"name": "textured specular", "pbrMetallicRoughness": dict(base, roughnessFactor=0.3),
         "extensions": {"KHR_materials_specular": {"specularFactor": 1.0, "specularTexture": {"index": 0},
                                                   "specularColorFactor": [1.0, 1.0, 1.0], "specularColorTexture": {"index": 0}},
                        "KHR_materials_ior": {"ior": 1.8}}},
        {"name": "textured film", "pbrMetallicRoughness": dict(base, baseColorFactor=[0.03, 0.03, 0.03, 1.0], roughnessFactor=0.25),
         "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceTexture": {"index": 1}, "iridescenceIor": 1.4,
                                                      "iridescenceThicknessMinimum": 150.0, "iridescenceThicknessMaximum": 450.0,
                                                      "iridescenceThicknessTexture": {"index": 1}}}},
        {"name": "textured translucent panel", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.45, 0.1, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8},
         "extensions": {"KHR_materials_diffuse_transmission": {
             "diffuseTransmissionFactor": 0.8, "diffuseTransmissionTexture": {"index": 0},
             "diffuseTransmissionColorFactor": [1.0, 1.0, 1.0], "diffuseTransmissionColorTexture": {"index": 0}}}}],
    "textures": [{"sampler": 0, "source": 0}, {"sampler": 0, "source": 1}, {"sampler": 0, "source": 2}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
    "images": [{"uri": data_uri("image/png", checker)}, {"uri": data_uri("image/png", stripes)}, {"uri": data_uri("image/png", ridges)}],
    "buffers": [{"byteLength": len(extensions_blob), "uri": data_uri("application/octet-stream", extensions_blob)}],
    "bufferViews": extension_views,
    "accessors": extension_accessors,
}
write("textured_extensions.gltf", extensions_gltf)


# coat_normal_glass.gltf: the thin pane under a full, smooth clear coat whose own normal map tilts
# the coat's normal by 70 degrees towards -x over the -x half (the map's first texel; u runs along
# +x) and leaves it the surface's over the +x half: the light above the pane's centre meets the -x
# half's coat at grazing angles, where Schlick's curve reflects far more (a fifth to two thirds of
# the light against 0.04 at normal incidence), so less passes there than through the +x half.
coat_glass = json.loads(json.dumps(pane))
coat_glass["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_clearcoat"]
coat_glass["materials"][1] = {
    "name": "coated pane", "doubleSided": True, "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
    "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                   "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatNormalTexture": {"index": 0}}}}
coat_glass["textures"] = [{"sampler": 0, "source": 0}]
coat_tilt = math.radians(70)
coat_glass["images"] = [{"uri": data_uri("image/png", png(2, 1, [[encode_normal(-math.sin(coat_tilt), 0.0), encode_normal(0.0, 0.0)]]))}]
write("coat_normal_glass.gltf", coat_glass)


# half_leaf.gltf: the 2 x 2 translucent leaf of scenes/materials/translucent_leaf.gltf (facing +y,
# diffuse transmission 0.7 of colour (0.7, 1, 0.2)) whose diffuseTransmissionTexture, sampled
# NEAREST, passes light through its -x half (alpha 255) and none through its +x half (alpha 0): the
# floor under each half gathers what the -x half passes, a known answer from rectangles' view
# factors (tests/translucent_light_test.cpp, tests/surface_layers_test.cpp), where the texture's
# mean would light both alike.
leaf_blob, leaf_meshes, leaf_views, leaf_accessors = build([([(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)], (0, 1, 0), 0)])
half_leaf = {
    "asset": {"version": "2.0", "generator": "caustica tests/data/gltf/make_textured.py"},
    "extensionsUsed": ["KHR_materials_diffuse_transmission"],
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": leaf_meshes,
    "materials": [
        {"name": "half-translucent leaf", "doubleSided": True,
         "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.45, 0.1, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8},
         "extensions": {"KHR_materials_diffuse_transmission": {
             "diffuseTransmissionFactor": 0.7, "diffuseTransmissionTexture": {"index": 0},
             "diffuseTransmissionColorFactor": [0.7, 1.0, 0.2]}}}],
    "textures": [{"sampler": 0, "source": 0}],
    "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}],
    "images": [{"uri": data_uri("image/png", png(2, 1, [[(255, 255, 255, 255), (255, 255, 255, 0)]]))}],
    "buffers": [{"byteLength": len(leaf_blob), "uri": data_uri("application/octet-stream", leaf_blob)}],
    "bufferViews": leaf_views,
    "accessors": leaf_accessors,
}
write("half_leaf.gltf", half_leaf)
