#!/usr/bin/env python3
"""The numbers the tracer's glTF reader is checked against, worked out here
from the glTF 2.0 specification alone, with Python's standard library (no
glTF package, nothing shared with the Rust reader): for each Khronos sample
model in scenes/khronos/, its triangle count (each node's placement
counted), the box of its placed vertices in the file's own coordinates, and
its cameras as eye, look-at point (one unit along the camera's -Z), up
(+Y), the horizontal field of view in degrees and the image's aspect.

    python3 xtask/peers/gltf_expected.py > scenes/khronos/expected.json

crates/scene-format/tests/gltf.rs compares the reader with it.
"""

import base64
import json
import math
import struct
import sys
from pathlib import Path

KHRONOS = Path(__file__).resolve().parents[2] / "scenes" / "khronos"
COMPONENT = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def matmul(a, b):
    """4x4 matrices as lists of rows."""
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def local_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    tx, ty, tz = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    s = [sx, sy, sz]
    t = [tx, ty, tz]
    return [[r[i][j] * s[j] for j in range(3)] + [t[i]] for i in range(3)] + [[0, 0, 0, 1]]


def apply(m, p, w=1.0):
    return [sum(m[i][k] * v for k, v in enumerate(list(p) + [w])) for i in range(3)]


def buffers(doc):
    out = []
    for b in doc["buffers"]:
        uri = b["uri"]
        out.append(base64.b64decode(uri.split(",", 1)[1]))
    return out


def accessor(doc, bufs, index):
    a = doc["accessors"][index]
    view = doc["bufferViews"][a["bufferView"]]
    fmt = "<" + COMPONENT[a["componentType"]]
    size = struct.calcsize(fmt)
    n = WIDTH[a["type"]]
    stride = view.get("byteStride") or size * n
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    data = bufs[view["buffer"]]
    return [
        [struct.unpack_from(fmt, data, start + i * stride + c * size)[0] for c in range(n)]
        for i in range(a["count"])
    ]


def walk(doc, node, parent, out):
    world = matmul(parent, local_matrix(doc["nodes"][node]))
    out.append((node, world))
    for child in doc["nodes"][node].get("children", []):
        walk(doc, child, world, out)


def expected(path):
    doc = json.loads(path.read_text())
    bufs = buffers(doc)
    scene = doc["scenes"][doc.get("scene", 0)]
    placed = []
    identity = [[float(i == j) for j in range(4)] for i in range(4)]
    for root in scene["nodes"]:
        walk(doc, root, identity, placed)
    triangles, lo, hi = 0, [math.inf] * 3, [-math.inf] * 3
    cameras = []
    for node, world in placed:
        n = doc["nodes"][node]
        if "mesh" in n:
            for prim in doc["meshes"][n["mesh"]]["primitives"]:
                assert prim.get("mode", 4) == 4, "only triangle lists in these samples"
                positions = accessor(doc, bufs, prim["attributes"]["POSITION"])
                count = doc["accessors"][prim["indices"]]["count"] if "indices" in prim else len(positions)
                triangles += count // 3
                for p in positions:
                    q = apply(world, p)
                    lo = [min(a, b) for a, b in zip(lo, q)]
                    hi = [max(a, b) for a, b in zip(hi, q)]
        if "camera" in n:
            c = doc["cameras"][n["camera"]]
            eye = apply(world, [0, 0, 0])
            forward = apply(world, [0, 0, -1], 0.0)
            up = apply(world, [0, 1, 0], 0.0)
            length = math.sqrt(sum(f * f for f in forward))
            look_at = [e + f / length for e, f in zip(eye, forward)]
            if c["type"] == "perspective":
                p = c["perspective"]
                aspect = p.get("aspectRatio", 4 / 3)
                fov = math.degrees(2 * math.atan(aspect * math.tan(p["yfov"] / 2)))
                cameras.append({"eye": eye, "look_at": look_at, "up": up, "fov": fov, "aspect": aspect})
            else:
                o = c["orthographic"]
                cameras.append({
                    "eye": eye, "look_at": look_at, "up": up,
                    "view_width": 2 * abs(o["xmag"]), "aspect": abs(o["xmag"] / o["ymag"]),
                })
    return {"triangles": triangles, "bounds": {"min": lo, "max": hi}, "cameras": cameras}


def main():
    result = {p.name: expected(p) for p in sorted(KHRONOS.glob("*.gltf"))}
    json.dump(result, sys.stdout, indent=2, sort_keys=True)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
