#!/usr/bin/env python3
"""Writes the shipped glTF scenes in scenes/ (run from anywhere: python3 tools/make_scenes.py).

The hair in these scenes is procedural (hairtrace's builtin:strand / builtin:ball, pulled in by
the scene extras key "hairtrace_builtin"), so the files hold only camera, lights and material and
stay small and readable.  Camera and light nodes are placed with a look-at rotation computed
here, since glTF stores node orientations as quaternions.
"""
import base64
import json
import math
import os
import sys
import struct
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), 'lib'))
from png_rgb8 import png_rgb8  # noqa: E402


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def look_at_rotation(eye, target, up=(0.0, 1.0, 0.0)):
    """Quaternion (x, y, z, w) turning a node so its -Z axis points from eye to target."""
    forward = normalize([t - e for t, e in zip(target, eye)])
    z = [-c for c in forward]
    x = normalize(cross(up, z))
    y = cross(z, x)
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]  # columns x, y, z
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [(m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s]
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2])
        q = [0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s]
    elif m[1][1] > m[2][2]:
        s = 2.0 * math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2])
        q = [(m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1])
        q = [(m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s]
    return [round(c, 6) for c in q]


def distance2(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b))


# Blond from the melanin of real hair: eumelanin 0.3, the `blond` preset of
# host/scene/hair_presets.cpp (sigma_a = (0.126, 0.209, 0.411) per unit radius through the
# Chiang et al. 2016 coefficients of host/fiber/material.cpp), the concentration of pbrt-v4's lock
# in ../shared/anchors/pbrt/ that reads golden.  Its absorption rises towards blue twice as steeply
# as the sigma_a = (0.07, 0.12, 0.26) these scenes had, which rendered grey-white.
WARM_BLOND = {
    "name": "warm_blond",
    "extras": {
        "model": "marschner",
        "eumelanin": 0.3,
        "eta": 1.55,
        "alpha_r_deg": -7.5,
        "beta_r_deg": 7.5,
        "eccentricity": 0.9,
    },
}


def checker_png(a, b, squares=2, texels_per_square=4):
    """squares x squares checker of sRGB colours a and b, each square a block of texels."""
    n = squares * texels_per_square
    rows = [[a if (x // texels_per_square + y // texels_per_square) % 2 == 0 else b for x in range(n)]
            for y in range(n)]
    return png_rgb8(n, n, rows)


def add_floor(doc, height, half, albedo, texture=None, uv_repeat=1.0):
    """Adds a square floor (two TRIANGLES, normals up, indexed) at y = height to a scene dict,
    with a diffuse material; the vertex data is embedded as a base64 data URI.  texture: PNG
    bytes for the material's baseColorTexture (embedded as a data URI, REPEAT sampler), mapped
    uv_repeat times across the floor."""
    positions = [(-half, height, -half), (half, height, -half), (half, height, half), (-half, height, half)]
    normals = [(0.0, 1.0, 0.0)] * 4
    indices = [0, 2, 1, 0, 3, 2]  # counter-clockwise seen from above: front face up
    blob = b"".join(struct.pack("<3f", *p) for p in positions)
    blob += b"".join(struct.pack("<3f", *n) for n in normals)
    blob += struct.pack("<6H", *indices)
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
             {"buffer": 0, "byteOffset": 48, "byteLength": 48},
             {"buffer": 0, "byteOffset": 96, "byteLength": 12}]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [-half, height, -half], "max": [half, height, half]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]
    attributes = {"POSITION": 0, "NORMAL": 1}
    material = {"name": "floor",
                "pbrMetallicRoughness": {"baseColorFactor": list(albedo) + [1.0],
                                         "metallicFactor": 0.0, "roughnessFactor": 1.0}}
    if texture is not None:
        # uv = (x, z) across the floor scaled to [0, uv_repeat]; v grows towards +z
        uvs = [((p[0] + half) / (2 * half) * uv_repeat, (p[2] + half) / (2 * half) * uv_repeat)
               for p in positions]
        blob += b"\x00" * ((4 - len(blob) % 4) % 4)  # float accessors start 4-byte aligned
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": 32})
        blob += b"".join(struct.pack("<2f", *uv) for uv in uvs)
        accessors.append({"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"})
        attributes["TEXCOORD_0"] = 3
        material["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
        doc["samplers"] = [{"wrapS": 10497, "wrapT": 10497, "magFilter": 9729, "minFilter": 9729}]
        doc["images"] = [{"name": "checker", "uri": "data:image/png;base64," + base64.b64encode(texture).decode()}]
        doc["textures"] = [{"source": 0, "sampler": 0}]
    doc["buffers"] = [{"byteLength": len(blob),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}]
    doc["bufferViews"] = views
    doc["accessors"] = accessors
    doc["materials"].append(material)
    doc["meshes"] = [{"name": "floor", "primitives": [
        {"mode": 4, "attributes": attributes, "indices": 2,
         "material": len(doc["materials"]) - 1}]}]
    doc["nodes"].append({"name": "floor", "mesh": 0})
    doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    return doc


def scene(builtin, eye, target, yfov_deg, aspect, lights, comment, material=None):
    """lights: list of (gltf light dict without intensity, position, aim, irradiance at aim)."""
    material = material or WARM_BLOND
    nodes = [{"name": "camera", "camera": 0, "translation": eye,
              "rotation": look_at_rotation(eye, target)}]
    gltf_lights = []
    for i, (light, position, aim, irradiance) in enumerate(lights):
        light = dict(light)
        # Point-like lights fall off with distance^2: state the irradiance wanted at the aim point.
        light["intensity"] = round(irradiance * distance2(position, aim), 1)
        gltf_lights.append(light)
        nodes.append({"name": light["name"], "translation": position,
                      "rotation": look_at_rotation(position, aim),
                      "extensions": {"KHR_lights_punctual": {"light": i}}})
    return {
        "asset": {"version": "2.0", "generator": "hairtrace tools/make_scenes.py",
                  "extras": {"comment": comment}},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": gltf_lights}},
        "scene": 0,
        "scenes": [{"name": builtin, "nodes": list(range(len(nodes))),
                    "extras": {"hairtrace_builtin": builtin,
                               "hairtrace_material": material["name"]}}],
        "nodes": nodes,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": round(math.radians(yfov_deg), 6),
                                     "aspectRatio": aspect, "znear": 0.1}}],
        "materials": [material],
    }


def with_hair_file(doc, uri, rotation):
    """Replaces a scene()'s built-in hair by a node that loads the hair file `uri` (relative to the
    scene's folder) through its extras.hairtrace_hair, rotated by `rotation` (glTF x, y, z, w),
    with the scene's hair material."""
    del doc["scenes"][0]["extras"]
    doc["nodes"].append({"name": "hair", "rotation": rotation,
                         "extras": {"hairtrace_hair": {"uri": uri, "material": doc["materials"][0]["name"]}}})
    doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    return doc


# Fig. 5 lighting: a key spot from behind and to the side (light through the fibres makes blond
# hair glow: the TT and TRT lobes) and a weak fill from the front-left for the surface (R) look.
BACK_KEY = {"name": "back_key", "type": "spot", "color": [1.0, 0.96, 0.9],
            "spot": {"innerConeAngle": round(math.radians(18), 6),
                     "outerConeAngle": round(math.radians(26), 6)}}
FRONT_FILL = {"name": "front_fill", "type": "point", "color": [0.9, 0.95, 1.0]}
# The demo's own changes to that pair.  The key's light crosses the fibres towards the camera (TT,
# golden) only in the upper part of the lock: lower down, the angles from the light above to the
# camera no longer line up.  There the lock had only the fill, which reaches the camera mostly as R,
# a reflection in the light's own colour, so with the cool fill the lower lock read silver-grey
# (linear saturation of its lit pixels 0.38 against 0.55 in the top quarter).  A weaker second
# back spot low behind the lock gives the lower part its own transmitted glow, and the fill in the
# key's warm white keeps its sheen warm: 0.49 against 0.58, the upper part as before.
WARM_FILL = dict(FRONT_FILL, color=BACK_KEY["color"])
LOW_BACK = dict(BACK_KEY, name="back_low")
TOP_KEY = {"name": "top_key", "type": "spot", "color": [1.0, 0.97, 0.92],
           "spot": {"innerConeAngle": round(math.radians(30), 6),
                    "outerConeAngle": round(math.radians(40), 6)}}

SCENES = {
    "default.gltf": scene(
        "strand", eye=[0.0, 0.0, 200.0], target=[0.0, 0.0, 0.0], yfov_deg=30.0, aspect=0.75,
        lights=[(BACK_KEY, [80.0, 90.0, -120.0], [0.0, 0.0, 0.0], 2.0),
                (WARM_FILL, [-100.0, 40.0, 150.0], [0.0, 0.0, 0.0], 0.3),
                (LOW_BACK, [80.0, -45.0, -120.0], [0.0, -25.0, 0.0], 0.3)],
        comment="The paper's Fig. 5 blond strand (builtin:strand), back/side lit, a second back "
                "light low for the lower part."),
    "strand_closeup.gltf": scene(
        "strand", eye=[0.0, 20.0, 45.0], target=[0.0, 20.0, 0.0], yfov_deg=30.0, aspect=1.5,
        lights=[(BACK_KEY, [50.0, 60.0, -70.0], [0.0, 20.0, 0.0], 2.0),
                (FRONT_FILL, [-60.0, 40.0, 80.0], [0.0, 20.0, 0.0], 0.3)],
        comment="Close-up of the upper part of builtin:strand: individual fibres resolved."),
    # builtin:strand ends at y = -50.1; the floor lies just below its tips.  A key spot from
    # above and in front throws the strand's shadow behind it onto the floor.
    "strand_on_floor.gltf": add_floor(scene(
        "strand", eye=[0.0, 40.0, 230.0], target=[0.0, -20.0, 0.0], yfov_deg=35.0, aspect=0.75,
        lights=[(TOP_KEY, [-40.0, 160.0, 90.0], [0.0, -52.0, 0.0], 2.0),
                (BACK_KEY, [80.0, 90.0, -120.0], [0.0, 0.0, 0.0], 1.0),
                (FRONT_FILL, [-100.0, 40.0, 150.0], [0.0, 0.0, 0.0], 0.2)],
        comment="builtin:strand standing on a grey diffuse floor (a TRIANGLES quad): hair "
                "shadows the floor."), height=-52.0, half=150.0, albedo=(0.6, 0.6, 0.6)),
    # The same with a checker-textured floor (terracotta and cream, 12 squares across): hair
    # over a base colour texture, a data: URI PNG with a REPEAT sampler.
    "strand_on_checker_floor.gltf": add_floor(scene(
        "strand", eye=[0.0, 40.0, 230.0], target=[0.0, -20.0, 0.0], yfov_deg=35.0, aspect=0.75,
        lights=[(TOP_KEY, [-40.0, 160.0, 90.0], [0.0, -52.0, 0.0], 2.0),
                (BACK_KEY, [80.0, 90.0, -120.0], [0.0, 0.0, 0.0], 1.0),
                (FRONT_FILL, [-100.0, 40.0, 150.0], [0.0, 0.0, 0.0], 0.2)],
        comment="builtin:strand standing on a checker-textured diffuse floor (baseColorTexture, "
                "TEXCOORD_0): hair shadows a textured surface."),
        height=-52.0, half=150.0, albedo=(1.0, 1.0, 1.0),
        texture=checker_png((190, 90, 60), (230, 220, 200)), uv_repeat=6.0),
    "ball.gltf": scene(
        "ball", eye=[65.6, 84.4, 187.5], target=[0.0, 0.0, 0.0], yfov_deg=30.0, aspect=1.0,
        lights=[(BACK_KEY, [120.0, 110.0, -140.0], [0.0, 0.0, 0.0], 2.0),
                (FRONT_FILL, [-130.0, 50.0, 150.0], [0.0, 0.0, 0.0], 0.3)],
        comment="Curly hair ball (builtin:ball), back/side lit."),
}


# The paper's blond (Zinke et al. 2004): eta = 1.55, sigma_a about 0.1 per unit radius (the
# paper's "very light hair" example, used for its 17% statement), caustic removal after
# Marschner 2003 with w_c = 15 deg, k_G = 2.5, delta eta' = 0.3 (Fig. 4 caption).  A slight warm
# tint: green is exactly 0.1, red a little lower, blue a little higher.  The model is the
# near-field one; tools/reproduce-paper switches models with --model / --fiber-field.
# Cem Yuksel's straight.hair (z-up, tips down to z = -22.8) from ../shared/data beside the
# checkout, turned y-up (-90 deg about x: z -> y, y -> -z) onto a floor just below its tips; front
# (+z after the turn) from the 3/4 view of host/scene/default_view.cpp, the floor scene's lights.
SCENES["straight_on_floor.gltf"] = with_hair_file(add_floor(scene(
    "straight", eye=[95.0, 55.0, 165.0], target=[0.0, 18.0, 3.0], yfov_deg=35.0, aspect=1.0,
    lights=[(TOP_KEY, [-50.0, 170.0, 110.0], [0.0, -23.0, 0.0], 2.0),
            (BACK_KEY, [80.0, 110.0, -120.0], [0.0, 20.0, 0.0], 1.0),
            (FRONT_FILL, [-110.0, 50.0, 150.0], [0.0, 20.0, 0.0], 0.2)],
    comment="Cem Yuksel's straight.hair (../shared/data) loaded by a node's extras.hairtrace_hair, on a "
            "grey diffuse floor."), height=-23.0, half=150.0, albedo=(0.6, 0.6, 0.6)),
    "../../shared/data/straight.hair", [-0.707107, 0.0, 0.0, 0.707107])


def paper_blond(scale=1.0, name="paper_blond"):
    return {
        "name": name,
        "extras": {
            "model": "zinke",
            "sigma_a": [round(scale * s, 4) for s in (0.08, 0.10, 0.14)],
            "eta": 1.55,
            "alpha_r_deg": -7.5,
            "beta_r_deg": 7.5,
            "eccentricity": 0.9,
            "caustic_wc_deg": 15.0,
            "caustic_kg": 2.5,
            "caustic_deta": 0.3,
        },
    }


PAPER_BLOND = paper_blond()
PAPER_BLOND_HALF = paper_blond(0.5, "paper_blond_half_sigma_a")

BALL_LIGHTS = [(BACK_KEY, [120.0, 110.0, -140.0], [0.0, 0.0, 0.0], 2.0),
               (FRONT_FILL, [-130.0, 50.0, 150.0], [0.0, 0.0, 0.0], 0.3)]

# Scenes of tools/reproduce-paper (docs/PAPER.md).  Square images like the paper's 1280 x 1280.
SCENES.update({
    "paper_fig5_strand.gltf": scene(
        "strand", eye=[0.0, 0.0, 200.0], target=[0.0, 0.0, 0.0], yfov_deg=30.0, aspect=1.0,
        lights=[(BACK_KEY, [80.0, 90.0, -120.0], [0.0, 0.0, 0.0], 2.0),
                (FRONT_FILL, [-100.0, 40.0, 150.0], [0.0, 0.0, 0.0], 0.3)],
        comment="Paper Fig. 5 a/b: the whole blond strand (2,500 x 100), paper blond material "
                "(sigma_a ~0.1 per radius, eta 1.55).", material=PAPER_BLOND),
    "paper_fig5_closeup.gltf": scene(
        "strand", eye=[0.0, 20.0, 45.0], target=[0.0, 20.0, 0.0], yfov_deg=30.0, aspect=1.0,
        lights=[(BACK_KEY, [50.0, 60.0, -70.0], [0.0, 20.0, 0.0], 2.0),
                (FRONT_FILL, [-60.0, 40.0, 80.0], [0.0, 20.0, 0.0], 0.3)],
        comment="Paper Fig. 5 right: close-up of the strand, fibres about 2 pixels wide at 256^2.",
        material=PAPER_BLOND),
    "paper_fig6_ball.gltf": scene(
        "ball", eye=[65.6, 84.4, 187.5], target=[0.0, 0.0, 0.0], yfov_deg=30.0, aspect=1.0,
        lights=BALL_LIGHTS,
        comment="Paper Fig. 6 a/b: hair ball (10,000 x 30), paper blond material.",
        material=PAPER_BLOND),
    "paper_fig6_ball_half_sigma.gltf": scene(
        "ball", eye=[65.6, 84.4, 187.5], target=[0.0, 0.0, 0.0], yfov_deg=30.0, aspect=1.0,
        lights=BALL_LIGHTS,
        comment="Paper Fig. 6 c: the hair ball with the absorption coefficients halved.",
        material=PAPER_BLOND_HALF),
    "paper_fig7_strand.gltf": scene(
        "strand", eye=[0.0, 10.0, 110.0], target=[0.0, 10.0, 0.0], yfov_deg=30.0, aspect=1.0,
        lights=[(BACK_KEY, [80.0, 100.0, -120.0], [0.0, 10.0, 0.0], 2.0),
                (FRONT_FILL, [-100.0, 50.0, 150.0], [0.0, 10.0, 0.0], 0.3)],
        comment="Paper Fig. 7: upper half of the strand, rendered at recursion depths 1..5.",
        material=PAPER_BLOND),
})


def main():
    out_dir = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes")
    for name, doc in SCENES.items():
        with open(os.path.join(out_dir, name), "w") as f:
            json.dump(doc, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
