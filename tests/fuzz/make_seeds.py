#!/usr/bin/env python3
"""Writes the seed corpora for the scene-loader fuzz targets into tests/fuzz/corpus/<target>/.

Small by design (the whole corpus stays well under 200 KB): a few valid files that reach every
branch of a loader (each optional array, hygiene repairs, every glTF feature the loader reads) and
a few malformed ones that stop at each kind of check.  Deterministic: rerunning rewrites the same
bytes, so `git status` after a rerun shows only intended changes.

    tests/fuzz/make_seeds.py [OUTPUT_DIR]      (default: tests/fuzz/corpus next to this script)
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'tools', 'lib'))
from png_rgb8 import png_rgb8  # noqa: E402

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def write(target, name, data):
    d = os.path.join(OUT, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def strands(n_strands, n_points, scale=1.0):
    """n_strands wavy strands of n_points each: a list of lists of (x, y, z)."""
    out = []
    for s in range(n_strands):
        out.append([(scale * (s + 0.3 * math.sin(i)), -scale * i, scale * 0.1 * s) for i in range(n_points)])
    return out


# ---- .hair -----------------------------------------------------------------------------------
def hair(hs, arrays=1 | 2 | 4 | 8 | 16, default_segments=0, default_thickness=0.05, info=b"seed",
         thickness=None, sig=b"HAIR", hair_count=None, point_count=None):
    pts = [p for h in hs for p in h]
    hc = len(hs) if hair_count is None else hair_count
    pc = len(pts) if point_count is None else point_count
    head = sig + struct.pack("<IIIIff3f", hc, pc, arrays, default_segments, default_thickness, 0.0,
                             0.9, 0.75, 0.5)
    head += info.ljust(88, b"\0")
    assert len(head) == 128
    body = b""
    if arrays & 1:
        body += b"".join(struct.pack("<H", len(h) - 1) for h in hs)
    if arrays & 2:
        body += b"".join(struct.pack("<3f", *p) for p in pts)
    if arrays & 4:
        th = thickness if thickness is not None else [0.05 + 0.001 * i for i in range(len(pts))]
        body += b"".join(struct.pack("<f", t) for t in th)
    if arrays & 8:
        body += b"".join(struct.pack("<f", 0.1) for _ in pts)
    if arrays & 16:
        body += b"".join(struct.pack("<3f", 0.9, 0.7, 0.5) for _ in pts)
    return head + body


T = "fuzz_hair_file"
write(T, "valid_all_arrays.hair", hair(strands(3, 4)))
write(T, "valid_segments_points.hair", hair(strands(2, 5), arrays=1 | 2))
write(T, "valid_default_segments.hair", hair(strands(3, 4), arrays=2, default_segments=3))
write(T, "valid_points_thickness.hair", hair(strands(2, 3), arrays=2 | 4, default_segments=2))
dup = strands(2, 4)
dup[0][2] = dup[0][1]                    # a zero-length segment (repaired)
dup.append([(5.0, 5.0, 5.0)] * 3)        # a strand that collapses to one point (dropped)
write(T, "repair_duplicates.hair", hair(dup))
write(T, "trailing_bytes.hair", hair(strands(1, 3)) + b"junk")
write(T, "bad_signature.hair", hair(strands(1, 3), sig=b"HAIX"))
write(T, "truncated_points.hair", hair(strands(2, 4))[:128 + 4 + 20])
write(T, "header_only.hair", hair(strands(1, 2))[:128])
write(T, "short_header.hair", b"HAIR" + b"\0" * 20)
write(T, "segments_exceed_points.hair", hair(strands(2, 4), point_count=7))
write(T, "huge_counts.hair", hair(strands(1, 2), hair_count=0xFFFFFFFF, point_count=0xFFFFFFFF))
write(T, "unknown_flag.hair", hair(strands(1, 3), arrays=1 | 2 | 4 | 64))
write(T, "nan_point.hair", hair([[(0, 0, 0), (float("nan"), 1, 0), (0, 2, 0)]]))
write(T, "zero_thickness.hair", hair(strands(1, 3), thickness=[0.1, 0.0, 0.1]))
write(T, "no_thickness_zero_default.hair", hair(strands(1, 3), arrays=1 | 2, default_thickness=0.0))


# ---- USC .data ---------------------------------------------------------------------------------
def usc(hs, count=None):
    out = struct.pack("<i", len(hs) if count is None else count)
    for h in hs:
        out += struct.pack("<i", len(h)) + b"".join(struct.pack("<3f", *p) for p in h)
    return out


T = "fuzz_usc_data"
write(T, "valid.data", usc(strands(3, 5, 0.01)))
write(T, "empty_roots.data", usc([[(0, 0, 0)], [], strands(1, 4)[0], [(1, 1, 1)]]))
write(T, "trailing_bytes.data", usc(strands(2, 3)) + b"\1\2\3")
write(T, "duplicates.data", usc([[(0, 0, 0), (0, 0, 0), (0, 1, 0)], [(1, 1, 1)] * 4]))
write(T, "negative_count.data", usc([], count=-1))
write(T, "count_exceeds_file.data", usc(strands(1, 3), count=1000))
write(T, "negative_vertices.data", struct.pack("<ii", 1, -5))
write(T, "truncated.data", usc(strands(2, 4))[:40])
write(T, "inf_point.data", usc([[(0, 0, 0), (float("inf"), 0, 0)]]))
write(T, "only_roots.data", usc([[(0, 0, 0)], [(1, 0, 0)]]))
write(T, "tiny.data", b"\1\0")


# ---- glTF / GLB ----------------------------------------------------------------------------------
def f32(values):
    return b"".join(struct.pack("<f", v) for v in values)


def hair_gltf(data_uri=True, extra=None):
    """A scene using every feature load_gltf reads: hierarchy with matrix and TRS transforms,
    LINE_STRIP with _RADIUS, LINES with u16 indices and chaining, a material with hair extras,
    a perspective + an orthographic camera, point/spot/directional lights."""
    pos = [0, 0, 0, 0, -1, 0.1, 0.1, -2, 0, 0.2, -3, 0.1]          # 4 points (LINE_STRIP)
    rad = [0.05, 0.05, 0.04, 0.03]
    pos2 = [1, 0, 0, 1, -1, 0, 1, -2, 0.1, 2, 0, 0, 2, -1, 0]       # 5 points (LINES)
    idx = [0, 1, 1, 2, 3, 4]                                        # chained 0-1-2, separate 3-4
    bin_ = f32(pos) + f32(rad) + f32(pos2) + b"".join(struct.pack("<H", i) for i in idx)
    views = [
        {"buffer": 0, "byteOffset": 0, "byteLength": 48},
        {"buffer": 0, "byteOffset": 48, "byteLength": 16},
        {"buffer": 0, "byteOffset": 64, "byteLength": 60},
        {"buffer": 0, "byteOffset": 124, "byteLength": 12},
    ]
    buf = {"byteLength": len(bin_)}
    if data_uri:
        buf["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bin_).decode()
    g = {
        "asset": {"version": "2.0", "generator": "hairtrace make_seeds.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 3]}],
        "nodes": [
            {"children": [1, 2], "translation": [0, 1, 0], "rotation": [0, 0.2588, 0, 0.9659],
             "scale": [2, 2, 2]},
            {"mesh": 0},
            {"mesh": 1, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, 0, 1]},
            {"children": [4, 5, 6, 7], "translation": [0, 0, 10]},
            {"camera": 0},
            {"camera": 1},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [5, 5, 5]},
            {"children": [8], "rotation": [-0.7071, 0, 0, 0.7071]},
            {"extensions": {"KHR_lights_punctual": {"light": 1}}},
        ],
        "meshes": [
            {"name": "strip", "primitives": [
                {"mode": 3, "attributes": {"POSITION": 0, "_RADIUS": 1}, "material": 0}]},
            {"primitives": [
                {"mode": 1, "attributes": {"POSITION": 2}, "indices": 3, "material": 1},
                # a strip: 5 vertices are 3 triangles (as TRIANGLES they were refused, so the
                # seed stopped here once triangles were read)
                {"mode": 5, "attributes": {"POSITION": 2}}]},
        ],
        "materials": [
            {"name": "blond", "extras": {"model": "zinke", "sigma_a": [0.06, 0.1, 0.2], "eta": 1.55,
                                         "beta_m": 0.3, "alpha_deg": 2, "unknown_key": 1}},
            {"name": "dark", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.1, 0.05, 1]},
             "extras": {"radius": 0.02, "eumelanin": 1.3}},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, -3, 0], "max": [0.2, 0, 0.1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 5, "type": "VEC3"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": views,
        "buffers": [buf],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1, "aspectRatio": 1.5}},
            {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 100}},
        ],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "spot", "color": [1, 0.9, 0.8], "intensity": 100,
             "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
            {"type": "directional", "intensity": 3},
        ]}},
    }
    if extra:
        extra(g)
    return g, bin_


def dumps(g):
    return json.dumps(g, separators=(",", ":"), sort_keys=True)


def glb(g, bin_):
    js = dumps(g).encode()
    js += b" " * (-len(js) % 4)
    chunks = struct.pack("<II", len(js), 0x4E4F534A) + js
    if bin_ is not None:
        b = bin_ + b"\0" * (-len(bin_) % 4)
        chunks += struct.pack("<II", len(b), 0x004E4942) + b
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


T = "fuzz_gltf"
g, b = hair_gltf()
write(T, "full_features.gltf", dumps(g))
g, b = hair_gltf(data_uri=False)
write(T, "full_features.glb", glb(g, b))

minimal = {
    "asset": {"version": "2.0"},
    "meshes": [{"primitives": [{"mode": 3, "attributes": {"POSITION": 0}}]}],
    "nodes": [{"mesh": 0}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," +
                 base64.b64encode(f32([0, 0, 0, 0, 1, 0, 0, 2, 1])).decode()}],
}
write(T, "minimal_no_scene.gltf", dumps(minimal))   # no scenes: roots found from children
write(T, "builtin_reference.gltf", dumps({
    "asset": {"version": "2.0", "extras": {"hairtrace_builtin": "ball?hairs=4&segments=3",
                                           "hairtrace_material": "m"}},
    "materials": [{"name": "m", "extras": {"model": "kajiya", "kd": [0.5, 0.4, 0.3]}}]}))
write(T, "builtin_scene_extras.gltf", dumps({
    "asset": {"version": "2.0"}, "scene": 0,
    "scenes": [{"nodes": [], "extras": {"hairtrace_builtin": "strand?hairs=2&segments=3&seed=7"}}]}))
# Malformed: each stops at a different check.
bad = json.loads(dumps(minimal))
bad["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [0]}]
bad["scenes"] = [{"nodes": [0]}]
write(T, "node_cycle.gltf", dumps(bad))
bad = json.loads(dumps(minimal))
bad["accessors"][0]["count"] = 4
write(T, "accessor_exceeds_view.gltf", dumps(bad))
bad = json.loads(dumps(minimal))
bad["accessors"][0]["byteOffset"] = 4
bad["bufferViews"][0]["byteStride"] = 4
write(T, "stride_too_small.gltf", dumps(bad))
bad = json.loads(dumps(minimal))
bad["nodes"][0]["scale"] = [0, 0, 0]
write(T, "zero_scale.gltf", dumps(bad))
bad = json.loads(dumps(minimal))
bad["meshes"][0]["primitives"][0]["mode"] = 1
bad["meshes"][0]["primitives"][0]["indices"] = 1
bad["accessors"].append({"bufferView": 0, "componentType": 5125, "count": 3, "type": "SCALAR"})
write(T, "lines_odd_bad_indices.gltf", dumps(bad))
write(T, "triangles_only.gltf", dumps({
    "asset": {"version": "2.0"}, "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"componentType": 5126, "count": 0, "type": "VEC3"}]}))
write(T, "not_json.gltf", "{\"asset\": {\"version\": \"2.0\"}, ")
g, b = hair_gltf(data_uri=False)
whole = glb(g, b)
write(T, "truncated.glb", whole[:len(whole) // 2])
write(T, "bad_chunk_length.glb", whole[:12] + struct.pack("<I", 0xFFFFFFF0) + whole[16:])



def textured(g, bin_, image_in_buffer, image=None, mime="image/png"):
    """Adds a textured quad to a hair_gltf scene: TEXCOORD_0 (float, or normalized u8 when the
    image is in the buffer), a baseColorTexture with a sampler, and an image (default a 2 x 2
    PNG) as a data: URI or as a bufferView."""
    png = image or png_rgb8(2, 2, [[(255, 0, 0), (0, 255, 0)], [(0, 0, 255), (255, 255, 255)]])
    bin_ = bin_ + b"\0" * (-len(bin_) % 4)
    quad = f32([0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1])
    if image_in_buffer:
        uv, uv_type = bytes([0, 0, 255, 0, 255, 255, 0, 255]), 5121
    else:
        uv, uv_type = f32([0, 0, 2, 0, 2, 2, 0, 2]), 5126
    first = len(g["bufferViews"])
    g["bufferViews"].append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(quad)})
    bin_ += quad
    g["bufferViews"].append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(uv)})
    bin_ += uv + b"\0" * (-len(uv) % 4)
    g["accessors"].append({"bufferView": first, "componentType": 5126, "count": 4, "type": "VEC3"})
    g["accessors"].append({"bufferView": first + 1, "componentType": uv_type, "count": 4, "type": "VEC2",
                           "normalized": uv_type != 5126})
    if image_in_buffer:
        g["bufferViews"].append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(png)})
        bin_ += png
        g["images"] = [{"bufferView": first + 2, "mimeType": mime}]
    else:
        g["images"] = [{"uri": "data:" + mime + ";base64," + base64.b64encode(png).decode()}]
    n = len(g["accessors"])
    g["materials"].append({"name": "checker", "pbrMetallicRoughness": {
        "baseColorFactor": [1, 0.5, 1, 1], "baseColorTexture": {"index": 0, "texCoord": 0}}})
    g["samplers"] = [{"wrapS": 33648, "wrapT": 33071, "magFilter": 9729}]
    g["textures"] = [{"source": 0, "sampler": 0}]
    g["meshes"].append({"primitives": [{"mode": 6, "attributes": {"POSITION": n - 2, "TEXCOORD_0": n - 1},
                                        "material": len(g["materials"]) - 1}]})
    g["nodes"].append({"mesh": len(g["meshes"]) - 1})
    g["scenes"][0]["nodes"].append(len(g["nodes"]) - 1)
    g["buffers"][0]["byteLength"] = len(bin_)
    if "uri" in g["buffers"][0]:
        g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bin_).decode()
    return g, bin_


# An 8 x 8 baseline JPEG (4:2:0, metadata stripped), written once by OpenImageIO's oiiotool:
# Python's standard library has no JPEG encoder, and the seed must be reproducible.
JPEG_8X8 = base64.b64decode(
    "/9j/4AAQSkZJRgABAQAAAQABAAD/4QAWRXhpZgAASUkqAAgAAAAAAAAAAAD/2wBDAAMCAgMCAgMDAwMEAwMEBQgF"
    "BQQEBQoHBwYIDAoMDAsKCwsNDhIQDQ4RDgsLEBYQERMUFRUVDA8XGBYUGBIUFRT/2wBDAQMEBAUEBQkFBQkUDQsN"
    "FBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBQUFBT/wAARCAAIAAgDASIAAhEB"
    "AxEB/8QAHwAAAQUBAQEBAQEAAAAAAAAAAAECAwQFBgcICQoL/8QAtRAAAgEDAwIEAwUFBAQAAAF9AQIDAAQRBRIh"
    "MUEGE1FhByJxFDKBkaEII0KxwRVS0fAkM2JyggkKFhcYGRolJicoKSo0NTY3ODk6Q0RFRkdISUpTVFVWV1hZWmNk"
    "ZWZnaGlqc3R1dnd4eXqDhIWGh4iJipKTlJWWl5iZmqKjpKWmp6ipqrKztLW2t7i5usLDxMXGx8jJytLT1NXW19jZ"
    "2uHi4+Tl5ufo6erx8vP09fb3+Pn6/8QAHwEAAwEBAQEBAQEBAQAAAAAAAAECAwQFBgcICQoL/8QAtREAAgECBAQD"
    "BAcFBAQAAQJ3AAECAxEEBSExBhJBUQdhcRMiMoEIFEKRobHBCSMzUvAVYnLRChYkNOEl8RcYGRomJygpKjU2Nzg5"
    "OkNERUZHSElKU1RVVldYWVpjZGVmZ2hpanN0dXZ3eHl6goOEhYaHiImKkpOUlZaXmJmaoqOkpaanqKmqsrO0tba3"
    "uLm6wsPExcbHyMnK0tPU1dbX2Nna4uPk5ebn6Onq8vP09fb3+Pn6/9oADAMBAAIRAxEAPwD1f/kWf+pM/wCEZ/7f"
    "/wDhC/tP5/2h9sz/ALXkb+2KKKK/M69eVCXLHz6tbNro12/RaWS/obKsqo5vRdas7Ncv2acvipwqPWpCb3m+uvxS"
    "vNznL//Z")


g, b = hair_gltf()
write(T, "textured_quad.gltf", dumps(textured(g, b, image_in_buffer=False)[0]))
g, b = hair_gltf(data_uri=False)
write(T, "textured_quad_jpeg.glb", glb(*textured(g, b, image_in_buffer=True, image=JPEG_8X8, mime="image/jpeg")))
g, b = hair_gltf(data_uri=False)
write(T, "textured_quad.glb", glb(*textured(g, b, image_in_buffer=True)))

# ---- builtin: specs ------------------------------------------------------------------------------
T = "fuzz_scene_builtin"
write(T, "strand_small", "strand?hairs=3&segments=4")
write(T, "ball_all_params", "ball?hairs=2&segments=5&seed=42&radius=0.25")
write(T, "strand_seed", "strand?seed=18446744073709551615&hairs=1&segments=1")
write(T, "empty_items", "ball?&&hairs=1&segments=2&")
write(T, "bad_name", "hedgehog?hairs=2")
write(T, "bad_value", "strand?hairs=-1&segments=1e3&radius=nan")

# ---- PLY polylines ---------------------------------------------------------------------------------
T = "fuzz_ply_file"
PLY_XYZ = "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
write(T, "ascii_counts.ply", "ply\nformat ascii 1.0\n" + (PLY_XYZ % 5).replace("property float z\n", "property float z\nproperty float radius\n")
      + "element strand 2\nproperty int vertex_count\nend_header\n0 0 0 .1\n0 1 0 .1\n0 2 0 .1\n1 0 0 .1\n1 1 0 .1\n3\n2\n")
write(T, "ascii_lists_width.ply", "ply\nformat ascii 1.0\ncomment c\n" + (PLY_XYZ % 3).replace("property float z\n", "property float z\nproperty float width\n")
      + "element curve 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1\n0 1 0 1\n1 1 0 1\n3 2 1 0\n")
edges_le = b"ply\nformat binary_little_endian 1.0\n" + (PLY_XYZ % 3).encode() + \
    b"property float thickness\nelement edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n" + \
    b"".join(struct.pack("<4f", i, i * i, 0, 0.1) for i in range(3)) + struct.pack("<4i", 0, 1, 1, 2)
write(T, "binary_le_edges.ply", edges_le)
lists_be = b"ply\nformat binary_big_endian 1.0\n" + (PLY_XYZ % 3).replace("float", "double").encode() + \
    b"element face 1\nproperty list uchar int vertex_indices\nelement hair 1\nproperty list ushort uint vertex_index\nend_header\n" + \
    b"".join(struct.pack(">3d", i, 1, i) for i in range(3)) + b"\3" + struct.pack(">3i", 0, 1, 2) + \
    struct.pack(">H3I", 3, 2, 1, 0)
write(T, "binary_be_lists.ply", lists_be)
write(T, "nan.ply", "ply\nformat ascii 1.0\n" + PLY_XYZ % 2 + "element strand 1\nproperty int nverts\nend_header\n0 0 0\nnan 1 0\n2\n")
write(T, "index_range.ply", "ply\nformat ascii 1.0\n" + PLY_XYZ % 2 + "element strand 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n0 1 0\n2 0 5\n")
write(T, "count_lies.ply", b"ply\nformat binary_little_endian 1.0\n" + (PLY_XYZ % 1000000).encode() + b"element strand 1\nproperty int count\nend_header\n")

# ---- OBJ line elements -----------------------------------------------------------------------------
T = "fuzz_obj_file"
write(T, "lines.obj", "v 0 0 0\nv 0 1 0\nv 0 2 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\nl 4 5\nl -1 -4\n")
write(T, "segments_faces.obj", "o hair\nv 0 0 0\nv 0 1 0\nv 0 2 0\nvn 0 0 1\nl 1 2\nl 2 3\nf 1 2 3\ng other\nl 3 1\n")
write(T, "bad_index.obj", "v 0 0 0\nl 1 7\n")
write(T, "inf.obj", "v 0 0 0\nv 1e999 0 0\nl 1 2\n")

# ---- pbrt-v4 curves --------------------------------------------------------------------------------
T = "fuzz_pbrt_file"
write(T, "bezier.pbrt", 'Shape "curve" "string type" "cylinder" "string basis" "bezier" "integer degree" 3 '
      '"integer splitdepth" 0 "float width" 0.1 "point3 P" [ 0 0 0 0 1 0 0 2 0 0 3 0 ]\n')
write(T, "bspline_widths.pbrt", 'Shape "curve" "string basis" "bspline" "integer degree" 2 "float width0" .2 '
      '"float width1" .1 "string type" "ribbon" "normal N" [0 0 1 0 0 1] "point P" [0 0 0 1 2 0 2 0 0 3 1 1]\n')
write(T, "scene.pbrt", 'LookAt 0 0 5 0 0 0 0 1 0\nCamera "perspective" "float fov" [30]\nWorldBegin\n'
      'LightSource "distant" "point3 to" [0 0 -1]\nAttributeBegin\nTranslate 1 2 3\nScale 2 2 2\n'
      'Rotate 30 0 0 1\nConcatTransform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]\nMaterial "hair"\n'
      'Shape "curve" "float width" 0.1 "point3 P" [0 0 0 0 0 1 0 0 2 0 0 3]\nShape "sphere"\nAttributeEnd\n'
      'Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]\nInclude "missing.pbrt"\n')
write(T, "nan.pbrt", 'Shape "curve" "point3 P" [0 0 0 0 nan 0 0 2 0 0 3 0]\n')
write(T, "self_include.pbrt", 'Import "input.pbrt"\n')
write(T, "unclosed.pbrt", 'Shape "curve" "point3 P" [0 0 0 0 1 0\n')
