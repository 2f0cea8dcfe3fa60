#!/usr/bin/env python3
"""Generates the binary test files of the OBJ/OFF/PLY/STL/glTF readers.

Run from tests/data:  python3 fmt_generate.py
Good files (tests/data):    fmt_be.ply, fmt_scene.gltf, fmt_triangle.glb
Broken files (tests/data/bad): bad_ply_truncated.ply, bad_stl_truncated.stl,
  bad_gltf_truncated.glb, bad_gltf_version.glb, bad_ply_huge_count.ply
The text files next to them are written by hand.
"""
import base64
import json
import struct


def ply_be():
    """Big-endian PLY: a skipped element with lists before the vertices,
    x/y/z of three different types, refs, a quad (vertex_index with ushort
    count) and a skipped element after the faces."""
    head = (
        "ply\nformat binary_big_endian 1.0\ncomment fmt_be\n"
        "element material 2\nproperty uchar id\nproperty list uchar float values\n"
        "element vertex 5\nproperty float x\nproperty short pad\nproperty double y\n"
        "property int z\nproperty int ref\n"
        "element face 2\nproperty uchar flags\nproperty list ushort uint vertex_index\nproperty int ref\n"
        "element edge 1\nproperty int v1\nproperty int v2\n"
        "end_header\n"
    ).encode()
    body = b""
    body += struct.pack(">BB3f", 0, 3, 0.1, 0.2, 0.3)
    body += struct.pack(">BB", 1, 0)
    verts = [(0.0, 0.0, 0, 10), (1.0, 0.0, 0, 11), (1.0, 1.0 / 3.0, 0, 12), (0.0, 1.0, 0, 13), (0.5, 0.5, 2, 14)]
    for x, y, z, r in verts:
        body += struct.pack(">fhdii", x, -1, y, z, r)
    body += struct.pack(">BH4Ii", 9, 4, 0, 1, 2, 3, 5)
    body += struct.pack(">BH3Ii", 9, 3, 0, 4, 1, 6)
    body += struct.pack(">ii", 0, 4)
    return head + body


def glb(json_obj, bin_data):
    j = json.dumps(json_obj, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    bin_data += b"\0" * (-len(bin_data) % 4)
    total = 12 + 8 + len(j) + 8 + len(bin_data)
    return (struct.pack("<III", 0x46546C67, 2, total) + struct.pack("<II", len(j), 0x4E4F534A) + j +
            struct.pack("<II", len(bin_data), 0x004E4942) + bin_data)


def scene_buffer():
    # 4 positions with a byte stride of 16 (4 padding bytes each).
    square = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)]
    pos = b"".join(struct.pack("<3f", *p) + b"\xff\xff\xff\xff" for p in square)
    strip = struct.pack("<4H", 0, 1, 2, 3)
    fan = struct.pack("<4B", 0, 1, 3, 2)
    return pos, strip, fan


def gltf_scene():
    """Node hierarchy (TRS, matrix), instancing, strip, fan, points, stride,
    uint16 and uint8 indices, a data URI buffer, a node outside the scene."""
    pos, strip, fan = scene_buffer()
    buf = pos + strip + fan
    s = 2 ** -0.5
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 3]}],
        "nodes": [
            {"translation": [10, 0, 0], "children": [1, 2]},
            {"mesh": 0, "scale": [2, 2, 2]},
            {"mesh": 0, "rotation": [0, 0, s, s]},
            {"mesh": 1, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1]},
            {"mesh": 2},
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 5},
                            {"attributes": {"POSITION": 0}, "mode": 0}]},
            {"primitives": [{"attributes": {"POSITION": 0}, "indices": 2, "mode": 6}]},
            {"primitives": [{"attributes": {"POSITION": 0}}]},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 4, "type": "SCALAR"},
            {"bufferView": 1, "byteOffset": 8, "componentType": 5121, "count": 4, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 64, "byteStride": 16},
            {"buffer": 0, "byteOffset": 64, "byteLength": 12},
        ],
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
    }
    return (json.dumps(doc, indent=1) + "\n").encode()


def glb_triangle():
    """A minimal valid .glb: one triangle, float positions, uint32 indices."""
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    idx = struct.pack("<3I", 0, 1, 2)
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"},
        ],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
        "buffers": [{"byteLength": 48}],
    }
    return glb(doc, pos + idx)


def main():
    with open("fmt_be.ply", "wb") as f:
        f.write(ply_be())
    with open("fmt_scene.gltf", "wb") as f:
        f.write(gltf_scene())
    with open("fmt_triangle.glb", "wb") as f:
        f.write(glb_triangle())

    # PLY binary cut in the middle of the faces.
    good = ply_be()
    with open("bad/bad_ply_truncated.ply", "wb") as f:
        f.write(good[:-20])
    # PLY announcing 2e9 vertices in a tiny file (memory guard).
    with open("bad/bad_ply_huge_count.ply", "wb") as f:
        f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\n"
                b"property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                b"end_header\n" + struct.pack("<3f", 0, 0, 0))
    # Binary STL: header does not start with "solid", announces 2 facets, has 1.
    header = b"truncated binary stl".ljust(80, b" ")
    facet = struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0)
    with open("bad/bad_stl_truncated.stl", "wb") as f:
        f.write(header + struct.pack("<I", 2) + facet)
    # GLB cut in the middle of its BIN chunk.
    tri = glb_triangle()
    with open("bad/bad_gltf_truncated.glb", "wb") as f:
        f.write(tri[:-10])
    # GLB of container version 1.
    with open("bad/bad_gltf_version.glb", "wb") as f:
        f.write(tri[:4] + struct.pack("<I", 1) + tri[8:])


if __name__ == "__main__":
    main()
