#!/usr/bin/env python3
"""A path-mode scene file of scenes/ rendered by Mitsuba 3, for its reference
image and for `cargo xtask bench --only path`.

    toml_scene.py scenes/materials.toml mitsuba --spp 64 --threads 2 --out m.exr
    toml_scene.py scenes/materials.toml reference --spp 4096 --passes 16 --out ref.exr

Mitsuba's scene is built from the TOML file itself, so the two cannot drift
apart; only what has an exact counterpart is handled, and anything else (a
key, a material, a shape) is an error naming it:

- the camera (right-handed, as Mitsuba's; our fov is the horizontal one), a
  box pixel filter; our `max_depth` is Mitsuba's minus 1;
- the environment: a latitude-longitude image, whose square starts half a
  turn from Mitsuba's (its centre column looks toward -z), hence an extra
  180 degrees; Mitsuba filters it bilinearly where we take the nearest
  texel, so it goes in with each texel repeated 4 x 4 times, which makes the
  two lookups agree but within an eighth of a texel of sharp edges. Or one
  colour (`constant`);
- the lab's diffuse material, `diffuse` (Lambert), its image texture a
  `bitmap` of the same texels (sRGB-decoded here, times the diffuse colour,
  rows flipped: Mitsuba's v = 0 is the image's top row, ours its bottom
  row), bilinear, the same wrap and scale; `emission` an `area` emitter;
- the physically based metal: white (F = 1, our Schlick F0 = 1)
  `roughconductor` / `conductor` with material `none`, another colour
  `principled` with metallic 1 (Schlick's F with F0 = base_color, as ours);
  glass (`transmission` 1, white): `roughdielectric` / `dielectric`, ior in
  air of index 1 (not Mitsuba's default 1.000277). GGX of alpha =
  roughness^2, visible-normal sampling, Smith's separable G in both;
- opaque materials wrapped in `twosided`: ours are two-sided (the shading
  frame faces the viewer), Mitsuba's are black from behind;
- spheres, quads (`rectangle`, [-1, 1]^2 at z = 0 facing +z, whose uv is
  ours), and boxes and OBJ meshes (flat-shaded, no `vn`) as triangle meshes
  built here as our `prepare` builds them, placed by the same transform
  (scale, then rotate about x, y, z, then translate).

Output and exit statuses as cornell.py's (whose Mitsuba set-up this reuses).
"""

import argparse
import math
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cornell as peer  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
ENVIRONMENT_UPSAMPLE = 4
# Our defaults (scene-format's model.rs).
DEFAULT_MAX_DEPTH = 7
DEFAULT_IOR = 1.5
DEFAULT_ROUGHNESS = 0.5
DEFAULT_BASE_COLOR = [0.8, 0.8, 0.8]
# [render] keys that change no expected value: the output's encoding, the
# number of samples and how they are spent.
RENDER_KEYS = {"integrator", "max_depth", "samples", "gamma", "saturation", "time_limit",
               "path_reuse", "camera_rays"}


def fail(message):
    sys.exit(f"toml_scene.py: {SCENE_FILE}: {message}")


def only(table, allowed, what):
    unknown = set(table) - set(allowed)
    if unknown:
        fail(f"{what} has {sorted(unknown)}, which this script does not map to Mitsuba")


def load_scene():
    with open(SCENE_FILE, "rb") as f:
        scene = tomllib.load(f)
    only(scene, {"camera", "render", "environment", "materials", "objects"}, "the file")
    render = scene.get("render", {})
    only(render, RENDER_KEYS, "[render]")
    if render.get("integrator") != "path":
        fail("[render] integrator must be \"path\"")
    return scene


def sensor(mi, camera, sampler):
    only(camera, {"eye", "look_at", "up", "fov", "width", "height", "handedness"}, "[camera]")
    if camera.get("handedness") != "right":
        fail("the camera must be right-handed (as Mitsuba's)")
    return {
        "type": "perspective",
        "fov": camera["fov"],
        "fov_axis": "x",  # our fov is the horizontal one
        "to_world": mi.ScalarTransform4f().look_at(
            origin=camera["eye"], target=camera["look_at"], up=camera.get("up", [0, 1, 0])),
        "film": {"type": "hdrfilm", "width": camera["width"], "height": camera["height"],
                 "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        "sampler": {"type": sampler},
    }


def environment(mi, env):
    import numpy as np
    only(env, {"image", "color", "strength", "rotate"}, "[environment]")
    strength = env.get("strength", 1)
    if "color" in env:
        return {"type": "constant",
                "radiance": {"type": "rgb", "value": [c * strength for c in env["color"]]}}
    path = os.path.join(os.path.dirname(SCENE_FILE), env["image"])
    texels = np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB,
                                              mi.Struct.Type.Float32, srgb_gamma=False))
    texels = np.repeat(np.repeat(texels, ENVIRONMENT_UPSAMPLE, axis=0),
                       ENVIRONMENT_UPSAMPLE, axis=1)
    turn = 180 + env.get("rotate", 0)
    return {"type": "envmap", "bitmap": mi.Bitmap(texels), "scale": strength,
            "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], turn)}


def srgb_to_linear(c):
    """The standard sRGB decoding, as ours (texture.rs)."""
    import numpy as np
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def image_texture(mi, texture, color):
    """Our image texture times `color`, as a Mitsuba bitmap of linear texels."""
    import numpy as np
    only(texture, {"image", "scale", "wrap"}, f"texture {texture}")
    path = os.path.join(os.path.dirname(SCENE_FILE), texture["image"])
    # The file's 8-bit values as they are (no conversion), decoded below.
    stored = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8,
                                     srgb_gamma=True)
    srgb = np.array(stored, dtype=np.float64) / 255.0
    linear = srgb_to_linear(srgb) * np.asarray(color, dtype=np.float64)
    scale = texture.get("scale", 1)
    su, sv = (scale, scale) if isinstance(scale, (int, float)) else scale
    return {"type": "bitmap",
            "bitmap": mi.Bitmap(np.ascontiguousarray(np.flipud(linear), dtype=np.float32)),
            "raw": True, "filter_type": "bilinear",
            "wrap_mode": texture.get("wrap", "repeat"),
            "to_uv": mi.ScalarTransform4f().scale([su, sv, 1])}


def bsdf(mi, name, material):
    """Our material as a Mitsuba BSDF, and its emission (None if it has none)."""
    emission = material.get("emission")
    if emission is not None and not any(emission):
        emission = None
    physical = {"base_color", "metallic", "roughness", "transmission"} & set(material)
    if physical:
        return physical_bsdf(material), emission
    only(material, {"diffuse", "emission", "texture"}, f"material {name}")
    diffuse = material.get("diffuse", [0, 0, 0])
    if "texture" in material:
        if not isinstance(material["texture"], dict) or "image" not in material["texture"]:
            fail(f"material {name}: only image textures are mapped")
        reflectance = image_texture(mi, material["texture"], diffuse)
    else:
        reflectance = {"type": "rgb", "value": diffuse}
    return twosided({"type": "diffuse", "reflectance": reflectance}), emission


def physical_bsdf(material):
    only(material, {"base_color", "metallic", "roughness", "transmission", "ior"},
         f"material {material}")
    color = material.get("base_color", DEFAULT_BASE_COLOR)
    roughness = material.get("roughness", DEFAULT_ROUGHNESS)
    alpha = roughness * roughness
    rough = {"distribution": "ggx", "alpha": alpha, "sample_visible": True} if alpha else {}
    if material.get("metallic", 0) == 1:
        if color == [1, 1, 1]:
            return twosided({"type": "roughconductor" if alpha else "conductor",
                             "material": "none"} | rough)
        # Mitsuba's principled metal: Schlick's F of F0 = base_color at the
        # half vector, GGX of alpha = max(roughness^2, 0.001), separable G.
        return twosided({"type": "principled", "base_color": {"type": "rgb", "value": color},
                         "metallic": 1.0, "roughness": roughness})
    if material.get("transmission", 0) == 1:
        if color != [1, 1, 1]:
            fail(f"material {material}: only clear glass (white base_color)")
        return {"type": "roughdielectric" if alpha else "dielectric",
                "int_ior": material.get("ior", DEFAULT_IOR), "ext_ior": 1.0} | rough
    fail(f"material {material}: our opaque dielectric (a Schlick layer over Lambert) "
         "has no exact Mitsuba counterpart")


def twosided(inner):
    return {"type": "twosided", "bsdf": inner}


def placement(transform):
    """Our transform table as (3x3 matrix, translation): Rz Ry Rx S, then +t."""
    import numpy as np
    transform = transform or {}
    if not isinstance(transform, dict):
        fail(f"transform {transform}: only the table form is mapped")
    only(transform, {"scale", "rotate", "translate"}, f"transform {transform}")
    scale = transform.get("scale", 1)
    scale = [scale] * 3 if isinstance(scale, (int, float)) else scale
    rx, ry, rz = (math.radians(a) for a in transform.get("rotate", [0, 0, 0]))

    def about(axis, a):
        c, s = math.cos(a), math.sin(a)
        if axis == "x":
            return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
        if axis == "y":
            return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])

    linear = about("z", rz) @ about("y", ry) @ about("x", rx) @ np.diag(scale)
    if np.linalg.det(linear) <= 0:
        fail(f"transform {transform}: a mirroring transform is not mapped")
    return linear, np.asarray(transform.get("translate", [0, 0, 0]), dtype=np.float64)


def box_triangles(lo, hi):
    """Our box's 12 triangles and their corners' uv (prepare.rs's
    box_triangles and quad_triangles): each face a quad facing out,
    corner + s u + t v with uv (s, t)."""
    import numpy as np
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    d = hi - lo
    x, y, z = np.array([d[0], 0, 0]), np.array([0, d[1], 0]), np.array([0, 0, d[2]])
    faces = [(lo, z, y), (np.array([hi[0], lo[1], lo[2]]), y, z), (lo, x, z),
             (np.array([lo[0], hi[1], lo[2]]), z, x), (lo, y, x),
             (np.array([lo[0], lo[1], hi[2]]), x, y)]
    triangles, uvs = [], []
    for corner, u, v in faces:
        far = corner + u + v
        triangles += [[corner, corner + u, corner + v], [far, corner + v, corner + u]]
        uvs += [[[0, 0], [1, 0], [0, 1]], [[1, 1], [0, 1], [1, 0]]]
    return np.array(triangles), np.array(uvs, dtype=np.float64)


def obj_triangles(path):
    """The triangles of an OBJ file without normals or uv: `v` and `f` lines
    (faces of more vertices as fans, negative indices from the end)."""
    import numpy as np
    vertices, triangles = [], []
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words or words[0].startswith("#"):
                continue
            if words[0] == "v":
                vertices.append([float(w) for w in words[1:4]])
            elif words[0] == "f":
                ids = [int(w.split("/")[0]) for w in words[1:]]
                ids = [i - 1 if i > 0 else len(vertices) + i for i in ids]
                triangles += [[ids[0], ids[k], ids[k + 1]] for k in range(1, len(ids) - 1)]
            elif words[0] in ("vn", "vt"):
                fail(f"{path}: `{words[0]}` lines are not mapped (flat meshes only)")
    return np.asarray(vertices, dtype=np.float64)[np.asarray(triangles)]


def mesh(mi, name, triangles, material, uvs=None):
    """A Mitsuba mesh of `triangles` (n x 3 corners), flat-shaded, with the
    corners' texture coordinates `uvs` (n x 3 x 2) when given."""
    import numpy as np
    n = len(triangles)
    props = mi.Properties()
    props["bsdf"] = material
    m = mi.Mesh(name, vertex_count=3 * n, face_count=n, props=props,
                has_vertex_normals=False, has_vertex_texcoords=uvs is not None)
    params = mi.traverse(m)
    # Each buffer as its own type: the JIT variants' mi.Float, the scalar
    # variant's dynamic array (where mi.Float is one number).
    def buffer(key, values):
        params[key] = type(params[key])(values)
    buffer("vertex_positions", triangles.reshape(-1).astype(np.float32))
    buffer("faces", np.arange(3 * n, dtype=np.uint32))
    if uvs is not None:
        buffer("vertex_texcoords", uvs.reshape(-1).astype(np.float32))
    params.update()
    return m


def shape(mi, k, obj, materials):
    only(obj, {"sphere", "quad", "box", "mesh", "material", "transform"}, f"object {k}")
    name = obj["material"]
    if not isinstance(name, str):
        fail(f"object {k}: only materials given by name are mapped")
    bsdf_object, emission = materials[name]
    transform = obj.get("transform")
    if "sphere" in obj or "quad" in obj:
        if transform is not None:
            fail(f"object {k}: a transformed sphere or quad is not mapped")
        result = analytic(mi, obj) | {"bsdf": bsdf_object}
    elif "box" in obj:
        linear, translate = placement(transform)
        triangles, uvs = box_triangles(obj["box"]["min"], obj["box"]["max"])
        result = mesh(mi, f"object-{k}", triangles @ linear.T + translate, bsdf_object, uvs)
    elif "mesh" in obj:
        only(obj["mesh"], {"obj", "smooth"}, f"object {k}'s mesh")
        if obj["mesh"].get("smooth", False):
            fail(f"object {k}: smooth meshes are not mapped (vertex normals differ)")
        path = os.path.join(os.path.dirname(SCENE_FILE), obj["mesh"]["obj"])
        linear, translate = placement(transform)
        triangles = obj_triangles(path) @ linear.T + translate
        result = mesh(mi, f"object-{k}", triangles, bsdf_object)
    else:
        fail(f"object {k}: no shape this script maps")
    if emission is not None:
        if not isinstance(result, dict):
            fail(f"object {k}: an emitting mesh is not mapped")
        result["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": emission}}
    return result


def analytic(mi, obj):
    if "sphere" in obj:
        s = obj["sphere"]
        return {"type": "sphere", "center": s["center"], "radius": s["radius"]}
    q = obj["quad"]
    corner, u, v = (q[k] for k in ("corner", "edge_u", "edge_v"))
    normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = math.sqrt(sum(x * x for x in normal))
    centre = [c + 0.5 * (a + b) for c, a, b in zip(corner, u, v)]
    # Mitsuba's rectangle is [-1, 1]^2 at z = 0 facing +z, its uv ((x + 1) / 2,
    # (y + 1) / 2): our quad's (s, t) when x runs along edge_u and y along edge_v.
    columns = [[0.5 * x for x in u], [0.5 * x for x in v], [x / length for x in normal], centre]
    rows = [[columns[c][r] for c in range(4)] for r in range(3)] + [[0, 0, 0, 1]]
    return {"type": "rectangle", "to_world": mi.ScalarTransform4f(rows)}


def mitsuba_scene(mi, sampler):
    scene = load_scene()
    render = scene.get("render", {})
    doc = {"type": "scene",
           "integrator": {"type": "path",
                          "max_depth": render.get("max_depth", DEFAULT_MAX_DEPTH) + 1},
           "sensor": sensor(mi, scene["camera"], sampler)}
    if "environment" in scene:
        doc["environment"] = environment(mi, scene["environment"])
    materials = {}
    for name, material in scene.get("materials", {}).items():
        inner, emission = bsdf(mi, name, material)
        materials[name] = (mi.load_dict(inner), emission)
    for k, obj in enumerate(scene.get("objects", [])):
        doc[f"shape-{k}"] = shape(mi, k, obj, materials)
    return mi.load_dict(doc)


SCENE_FILE = None


def main():
    global SCENE_FILE
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="a scene file (path mode)")
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
    SCENE_FILE = os.path.abspath(args.scene)
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
