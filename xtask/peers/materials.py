#!/usr/bin/env python3
"""scenes/materials.toml rendered by Mitsuba 3, for its reference image and for
`cargo xtask bench --only path`.

    materials.py mitsuba --spp 64 --threads 2 --out m.exr
    materials.py reference --spp 4096 --passes 16 --out ref.exr

The Mitsuba scene is built from the TOML file itself (only what that scene
uses: a camera, an environment image, quads and spheres, the lab's diffuse
material and the physically based metal and glass), so the two cannot drift
apart: an unknown key is an error here. Our `max_depth` is Mitsuba's minus 1;
our latitude-longitude square starts half a turn from Mitsuba's (its centre
column looks toward -z), hence the environment's extra 180 degrees. Mitsuba
filters the environment bilinearly where we take the nearest texel: the image
goes in with each texel repeated 4 x 4 times, which makes the two lookups agree
but within an eighth of a texel of the studio's sharp edges.

Output and exit statuses as cornell.py's (whose Mitsuba set-up this reuses).
"""

import argparse
import json
import math
import os
import sys
import time
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cornell as peer  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENE = os.path.join(ROOT, "scenes", "materials.toml")
UPSAMPLE = 4


def load_scene():
    with open(SCENE, "rb") as f:
        scene = tomllib.load(f)
    known = {"camera", "render", "environment", "materials", "objects"}
    if set(scene) - known:
        sys.exit(f"materials.py: {SCENE} has {sorted(set(scene) - known)}, not handled here")
    return scene


def sensor(camera, sampler):
    if camera.get("handedness") != "right":
        sys.exit("materials.py: the camera must be right-handed (as Mitsuba's)")
    return {
        "type": "perspective",
        "fov": camera["fov"],
        "fov_axis": "x",  # our fov is the horizontal one
        "to_world": peer_look_at(camera),
        "film": {"type": "hdrfilm", "width": camera["width"], "height": camera["height"],
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": sampler},
    }


def peer_look_at(camera):
    import mitsuba as mi
    return mi.ScalarTransform4f().look_at(origin=camera["eye"], target=camera["look_at"],
                                           up=camera.get("up", [0, 1, 0]))


def environment(env):
    import mitsuba as mi
    import numpy as np
    if set(env) - {"image", "strength", "rotate"}:
        sys.exit(f"materials.py: [environment] keys {sorted(env)} not handled")
    path = os.path.join(ROOT, "scenes", env["image"])
    texels = np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB,
                                              mi.Struct.Type.Float32, srgb_gamma=False))
    texels = np.repeat(np.repeat(texels, UPSAMPLE, axis=0), UPSAMPLE, axis=1)
    turn = 180 + env.get("rotate", 0)
    return {"type": "envmap", "bitmap": mi.Bitmap(texels), "scale": env.get("strength", 1),
            "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], turn)}


def bsdf(material):
    kinds = {"diffuse", "base_color", "metallic", "roughness", "transmission", "ior"}
    if set(material) - kinds:
        sys.exit(f"materials.py: material keys {sorted(set(material) - kinds)} not handled")
    if "diffuse" in material:
        return {"type": "diffuse", "reflectance": {"type": "rgb", "value": material["diffuse"]}}
    roughness = material.get("roughness", 0.5)
    alpha = roughness * roughness
    rough = {"distribution": "ggx", "alpha": alpha, "sample_visible": True} if alpha else {}
    if material.get("metallic", 0) == 1:
        if material.get("base_color") != [1, 1, 1]:
            sys.exit("materials.py: only white metal (F = 1, Mitsuba's material 'none')")
        return {"type": "roughconductor" if alpha else "conductor", "material": "none"} | rough
    if material.get("transmission", 0) == 1:
        return {"type": "roughdielectric" if alpha else "dielectric",
                "int_ior": material.get("ior", 1.5), "ext_ior": 1.0} | rough
    sys.exit(f"materials.py: material {material} not handled")


def shape(obj, bsdfs):
    import mitsuba as mi
    material = {"type": "ref", "id": obj["material"]}
    if "sphere" in obj:
        s = obj["sphere"]
        return {"type": "sphere", "center": s["center"], "radius": s["radius"], "bsdf": material}
    if "quad" in obj:
        q = obj["quad"]
        corner, u, v = (q[k] for k in ("corner", "edge_u", "edge_v"))
        normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                  u[0] * v[1] - u[1] * v[0]]
        length = math.sqrt(sum(x * x for x in normal))
        centre = [c + 0.5 * (a + b) for c, a, b in zip(corner, u, v)]
        # Mitsuba's rectangle is [-1, 1]^2 at z = 0 facing +z.
        columns = [[0.5 * x for x in u], [0.5 * x for x in v],
                   [x / length for x in normal], centre]
        rows = [[columns[c][r] for c in range(4)] for r in range(3)] + [[0, 0, 0, 1]]
        return {"type": "rectangle", "to_world": mi.ScalarTransform4f(rows), "bsdf": material}
    sys.exit(f"materials.py: object {obj} not handled")


def mitsuba_scene(mi, sampler):
    scene = load_scene()
    render = scene.get("render", {})
    doc = {"type": "scene",
           "integrator": {"type": "path", "max_depth": render.get("max_depth", 7) + 1},
           "sensor": sensor(scene["camera"], sampler),
           "environment": environment(scene["environment"])}
    for name, material in scene["materials"].items():
        doc[name] = bsdf(material) | {"id": name}
    for k, obj in enumerate(scene["objects"]):
        doc[f"shape-{k}"] = shape(obj, scene["materials"])
    return mi.load_dict(doc)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    for name in ("mitsuba", "reference"):
        p = sub.add_parser(name)
        p.add_argument("--spp", type=int, required=True)
        p.add_argument("--threads", type=int, default=os.cpu_count())
        p.add_argument("--out", required=True)
        p.add_argument("--sampler", choices=["independent", "multijitter"],
                       default="multijitter" if name == "reference" else "independent")
        if name == "mitsuba":
            p.add_argument("--variant", choices=["llvm_ad_rgb", "scalar_rgb"],
                           default="llvm_ad_rgb")
            p.add_argument("--seed", type=int, default=0)
        else:
            p.add_argument("--passes", type=int, default=16)
            p.add_argument("--half", action="store_true", help="half floats (16-bit)")
    args = parser.parse_args()
    peer.confine(args.threads)
    # cornell.py's renderers, given this scene.
    peer.mitsuba_scene = mitsuba_scene
    camera = load_scene()["camera"]
    peer.PIXELS = camera["width"] * camera["height"]
    if args.command == "mitsuba":
        peer.mitsuba(args)
    else:
        peer.reference(args)


if __name__ == "__main__":
    main()
