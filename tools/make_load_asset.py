#!/usr/bin/env python3
"""Writes a textured 100k-triangle glTF (GLB) for `caustica bench load`: a bumpy sphere of 102,400
triangles with TEXCOORD_0, a 2048x2048 base colour texture, a 2048x2048 normal map, a 1024x1024
metallic-roughness texture, and a 4096x4096 image that no material uses (the loader must not decode
it). Usage: python3 tools/make_load_asset.py OUT.glb"""
import json, math, random, struct, sys, zlib


def png(width, height, pixel):  # pixel(x, y) -> 4 bytes; rows built with bytes joins for speed
    rows = []
    for y in range(height):
        rows.append(b"\x00" + b"".join(pixel(x, y) for x in range(width)))
    raw = b"".join(rows)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def texture_images():
    random.seed(1)
    noise = [bytes([random.randrange(256) for _ in range(4 * 256)]) for _ in range(64)]  # tiles of noise, reused
    def tiled(size):
        return lambda x, y: noise[(y * 7 + x // 256) % 64][(x % 256) * 4:(x % 256) * 4 + 4]
    return [png(2048, 2048, tiled(2048)), png(2048, 2048, lambda x, y: b"\x80\x80\xff\xff"),
            png(1024, 1024, tiled(1024)), png(4096, 4096, tiled(4096))]


def sphere(slices=320, stacks=160):
    positions, normals, uvs, indices = [], [], [], []
    for j in range(stacks + 1):
        v = j / stacks
        theta = v * math.pi
        for i in range(slices + 1):
            u = i / slices
            phi = u * 2 * math.pi
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            r = 1 + 0.02 * math.sin(12 * phi) * math.sin(8 * theta)
            positions.append(tuple(r * c for c in n))
            normals.append(n)
            uvs.append((u, v))
    for j in range(stacks):
        for i in range(slices):
            a, b = j * (slices + 1) + i, (j + 1) * (slices + 1) + i
            indices += [a, a + 1, b, a + 1, b + 1, b]
    return positions, normals, uvs, indices


def main(out):
    positions, normals, uvs, indices = sphere()
    images = texture_images()
    chunks = [b"".join(struct.pack("<3f", *p) for p in positions), b"".join(struct.pack("<3f", *n) for n in normals),
              b"".join(struct.pack("<2f", *t) for t in uvs), struct.pack("<%dI" % len(indices), *indices)] + images
    blob, views = b"", []
    for c in chunks:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(c)})
        blob += c + b"\0" * (-len(c) % 4)
    n = len(positions)
    gltf = {
        "asset": {"version": "2.0", "generator": "caustica tools/make_load_asset.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "accessors": [{"bufferView": 0, "count": n, "type": "VEC3", "componentType": 5126, "min": [-1.1] * 3, "max": [1.1] * 3},
                      {"bufferView": 1, "count": n, "type": "VEC3", "componentType": 5126},
                      {"bufferView": 2, "count": n, "type": "VEC2", "componentType": 5126},
                      {"bufferView": 3, "count": len(indices), "type": "SCALAR", "componentType": 5125}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 2}},
                       "normalTexture": {"index": 1}}],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}],
        "images": [{"bufferView": 4 + k, "mimeType": "image/png"} for k in range(4)],
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    with open(out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(blob)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(blob), 0x004E4942) + blob)
    print("%s: %d triangles, %d images (one unused), %.1f MiB" % (out, len(indices) // 3, len(images), (28 + len(text) + len(blob)) / 2**20))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
