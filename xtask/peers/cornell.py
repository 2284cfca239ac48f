#!/usr/bin/env python3
"""Mitsuba 3's Cornell box rendered by the path tracer's peers, for
`cargo xtask bench --only path`.

    cornell.py mitsuba --variant llvm_ad_rgb --sampler independent --spp 64 --threads 2 --out m.exr
    cornell.py cycles --spp 64 --threads 2 --out c.exr
    cornell.py reference --spp 8192 --out ref.exr
    cornell.py compare a.exr b.exr

Every render is the scene of `cornell_box.py` (the same as scenes/cornell-box.toml)
at 256x256 with a box pixel filter, written as a 32-bit float linear Rec.709 EXR,
and prints one JSON line: `seconds` is the render alone (after a warm-up render
that loads kernels; less the JIT compilation left in it, `jit_s`), `spp` the
samples per pixel rendered, `cpu_s` the CPU time (about threads x seconds when
the threads are used), and the settings. Exit status: 0 done, 3 the renderer is
not installed (one line on stderr saying so), 2 bad arguments, 1 anything else.
`reference` and `compare` also need numpy and OpenEXR (pip install OpenEXR).
"""

import argparse
import json
import math
import os
import resource
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cornell_box as box  # noqa: E402

NOT_INSTALLED = 3
# Pixels of an image, for paths/s (toml_scene.py renders other scenes).
PIXELS = box.SIZE**2


def not_installed(message):
    print(message, file=sys.stderr)
    sys.exit(NOT_INSTALLED)


def confine(threads):
    """Keeps the process on `threads` CPUs: Cycles 5.0 asked for 1 thread keeps
    a second one busy (twice the CPU time for the same work)."""
    cpus = sorted(os.sched_getaffinity(0))
    if threads < len(cpus):
        os.sched_setaffinity(0, cpus[-threads:])


def timed(render):
    """Wall and CPU seconds of `render()`, and what it returned."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    start = time.perf_counter()
    result = render()
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_SELF)
    cpu = after.ru_utime + after.ru_stime - usage.ru_utime - usage.ru_stime
    return seconds, cpu, result


def report(args, renderer, spp, seconds, cpu, **extra):
    line = {"renderer": renderer, "spp": spp, "threads": args.threads, "seed": args.seed,
            "seconds": round(seconds, 4), "cpu_s": round(cpu, 4),
            "paths_per_s": round(PIXELS * spp / seconds), "out": args.out}
    print(json.dumps(line | extra))


# ---------------------------------------------------------------- Mitsuba 3


def load_mitsuba(variant, threads):
    try:
        import mitsuba as mi
        import drjit as dr
    except ImportError:
        not_installed("Mitsuba 3: skipped, not installed (pip install mitsuba)")
    try:
        mi.set_variant(variant)
    except (ImportError, AttributeError) as e:
        not_installed(f"Mitsuba 3: skipped, variant {variant} unavailable ({e})")
    if variant.startswith("llvm") and dr.detail.llvm_version() < (17, 0, 0):
        # LLVM 15 aborts the process on Mitsuba 3.9's kernels ("Cannot select
        # fminimum": x86 lowering of llvm.minimum came later); 19 works.
        version = ".".join(map(str, dr.detail.llvm_version()))
        not_installed(f"Mitsuba 3: skipped, {variant} found LLVM {version}, needs 17 or "
                      "later (apt-get install libllvm19, or set DRJIT_LIBLLVM_PATH)")
    # One pool serves both the LLVM kernels and scalar_rgb's render blocks.
    dr.set_thread_count(threads)
    return mi, dr


def mitsuba_scene(mi, sampler):
    scene = mi.cornell_box()
    box.check_against_mitsuba()
    film = scene["sensor"]["film"]
    film["rfilter"] = {"type": "box"}  # cornell_box() has a Gaussian
    assert (film["width"], film["height"]) == (box.SIZE, box.SIZE)
    scene["sensor"]["sampler"] = {"type": sampler}
    return mi.load_dict(scene)


def mitsuba_render(mi, dr, scene, spp, seed):
    """The image, and the samples per pixel rendered: multijitter rounds the
    count up to a product of two near integers (32 -> 35, 128 -> 132)."""
    image = mi.render(scene, spp=spp, seed=seed)
    dr.eval(image)
    dr.sync_thread()
    return image, scene.sensors()[0].sampler().sample_count()


def mitsuba(args):
    mi, dr = load_mitsuba(args.variant, args.threads)
    scene = mitsuba_scene(mi, args.sampler)
    # A first render loads what every render needs. The LLVM kernel of the
    # independent sampler is the same for any count above 1, but
    # multijitter's changes with the count: what compiling is left in the
    # timed render, Dr.Jit's kernel history measures, and it is taken off.
    mitsuba_render(mi, dr, scene, min(args.spp, 2), args.seed + 1)
    jit = args.variant.startswith("llvm")
    if jit:
        dr.set_flag(dr.JitFlag.KernelHistory, True)
        dr.kernel_history_clear()
    wall, cpu, (image, spp) = timed(lambda: mitsuba_render(mi, dr, scene, args.spp, args.seed))
    # Code generation and LLVM compilation, in ms (0 for a cached kernel).
    jit_s = sum(k.get("codegen_time", 0) + k.get("backend_time", 0)
                for k in dr.kernel_history()) / 1000 if jit else 0.0
    # Mitsuba 3.9's EXR writer deadlocks in a pool of one thread.
    dr.set_thread_count(max(args.threads, 2))
    mi.Bitmap(image).write(args.out)
    report(args, f"mitsuba-{args.variant}-{args.sampler}", spp, wall - jit_s, cpu,
           wall_s=round(wall, 4), jit_s=round(jit_s, 4), version=mi.__version__)


def reference(args):
    """The mean of `passes` independent renders (seeds 0..passes-1): their spread
    estimates the reference's own noise."""
    import numpy as np
    import OpenEXR  # noqa: F401 (written at the end: missing, fail before the work)

    mi, dr = load_mitsuba("llvm_ad_rgb", args.threads)
    scene = mitsuba_scene(mi, args.sampler)
    if args.spp % args.passes:
        sys.exit(f"--spp {args.spp} is not a multiple of --passes {args.passes}")
    each = args.spp // args.passes
    images, spp, start = [], 0, time.perf_counter()
    for seed in range(args.passes):
        image, rendered = mitsuba_render(mi, dr, scene, each, seed)
        images.append(np.array(image, dtype=np.float64))
        spp += rendered
        print(f"pass {seed + 1}/{args.passes}: {time.perf_counter() - start:.0f} s",
              file=sys.stderr, flush=True)
    stack = np.stack(images)
    mean = stack.mean(axis=0)
    # Standard error of the mean per pixel and channel, as one RMS figure.
    noise = float(np.sqrt((stack.var(axis=0, ddof=1) / args.passes).mean()))
    write_exr(args.out, mean.astype(np.float32), half=args.half)
    print(json.dumps({"renderer": f"mitsuba-llvm_ad_rgb-{args.sampler}", "spp": spp,
                      "passes": args.passes, "seeds": f"0..{args.passes - 1}",
                      "seconds": round(time.perf_counter() - start, 1), "threads": args.threads,
                      "noise_rmse": noise, "mean": float(mean.mean()),
                      "version": mi.__version__, "out": args.out}))


# ---------------------------------------------------------------- Cycles


def cycles(args):
    try:
        import bpy
    except ImportError:
        not_installed("Cycles: skipped, bpy not installed (pip install bpy; it needs "
                      f"the Python of its Blender release, this is {sys.version.split()[0]})")
    global mathutils
    import mathutils

    scene = cycles_scene(bpy, args)
    # The first render loads the kernels and builds the BVH; time the second.
    scene.cycles.samples = 1
    bpy.ops.render.render()
    scene.cycles.samples = args.spp
    seconds, cpu, _ = timed(lambda: bpy.ops.render.render())
    bpy.data.images["Render Result"].save_render(filepath=args.out)
    report(args, "cycles", args.spp, seconds, cpu, version=bpy.app.version_string,
           sampling_pattern=scene.cycles.sampling_pattern)


def cycles_scene(bpy, args):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.seed = args.seed
    c.use_adaptive_sampling = False
    c.use_denoising = False
    # Cycles counts bounces after the first hit: Mitsuba's max_depth 8 is 6.
    bounces = box.MITSUBA_MAX_DEPTH - 2
    c.max_bounces = bounces
    for kind in ("diffuse", "glossy", "transmission", "transparent_max"):
        setattr(c, f"{kind}_bounces", bounces)
    c.sample_clamp_direct = c.sample_clamp_indirect = 0  # 0 = no clamping
    c.use_light_tree = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    scene.render.resolution_x = scene.render.resolution_y = box.SIZE
    scene.render.resolution_percentage = 100
    scene.render.use_compositing = scene.render.use_sequencer = False
    scene.view_settings.view_transform = "Standard"  # the EXR is linear anyway
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGB", "32"
    settings.exr_codec = "ZIP"

    # A new world has a grey background (0.05) lighting the box through its
    # open front: none at all is black.
    scene.world = None

    materials = {name: lambert(bpy, name, rgb) for name, rgb in box.ALBEDO.items()}
    materials["light"] = lambert(bpy, "light", box.ALBEDO["white"], box.LIGHT_RADIANCE)
    for name, (kind, material, *_rest) in box.SHAPES.items():
        m = box.matrix(name)
        corners = RECTANGLE if kind == "rectangle" else CUBE
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([box.apply(m, v, 1) for v in corners[0]], [], corners[1])
        obj = bpy.data.objects.new(name, mesh)
        obj.data.materials.append(materials["light" if name == box.EMITTER else material])
        scene.collection.objects.link(obj)

    camera = bpy.data.cameras.new("camera")
    camera.lens_unit = "FOV"
    camera.sensor_fit = "AUTO"  # the fov on the larger axis; the image is square
    camera.angle = math.radians(box.CAMERA["fov"])
    camera.clip_start, camera.clip_end = 0.001, 100
    obj = bpy.data.objects.new("camera", camera)
    # Blender's camera looks down its -z with +x to the image's right;
    # Mitsuba's frame is (left, up, forward).
    left, up, fwd = box.camera_frame()
    right, back = [-x for x in left], [-x for x in fwd]
    eye = box.CAMERA["eye"]
    rows = [[right[i], up[i], back[i], eye[i]] for i in range(3)] + [[0, 0, 0, 1]]
    obj.matrix_world = mathutils.Matrix(rows)  # a plain list would be read by columns
    scene.collection.objects.link(obj)
    scene.camera = obj
    return scene


# A rectangle [-1, 1]^2 at z = 0 facing +z, and a cube [-1, 1]^3 facing out
# (counter-clockwise seen from outside), as Mitsuba's.
RECTANGLE = ([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [(0, 1, 2, 3)])
CUBE = (
    [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)],
    [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)],
)


def lambert(bpy, name, albedo, radiance=None):
    """A one-sided Lambertian material, as Mitsuba's `diffuse` (black from
    behind), emitting `radiance` from its front when given."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None:  # Blender before 5.0 (where it is always there)
        mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*albedo, 1)
    diffuse.inputs["Roughness"].default_value = 0  # Lambert, not Oren-Nayar
    front = diffuse.outputs["BSDF"]
    if radiance:
        emission = nodes.new("ShaderNodeEmission")
        # Strength 1 on a mesh is radiance = colour (the light's own pixels
        # show the colour), so Mitsuba's radiance goes in as the colour.
        emission.inputs["Color"].default_value = (*radiance, 1)
        emission.inputs["Strength"].default_value = 1
        add = nodes.new("ShaderNodeAddShader")
        links.new(front, add.inputs[0])
        links.new(emission.outputs["Emission"], add.inputs[1])
        front = add.outputs["Shader"]
        # Light sampling picks the front only, where it emits.
        mat.cycles.emission_sampling = "FRONT"
    black = nodes.new("ShaderNodeEmission")
    black.inputs["Strength"].default_value = 0  # absorbs, emits nothing
    geometry = nodes.new("ShaderNodeNewGeometry")
    mix = nodes.new("ShaderNodeMixShader")
    links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
    links.new(front, mix.inputs[1])
    links.new(black.outputs["Emission"], mix.inputs[2])
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return mat


# ---------------------------------------------------------------- images


def read_exr(path):
    """An EXR's RGB channels as a float64 array (height, width, 3)."""
    import numpy as np
    import OpenEXR

    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "RGB" in channels:
            rgb = channels["RGB"].pixels
        else:
            rgb = np.stack([channels[c].pixels for c in "RGB"], axis=-1)
    return np.asarray(rgb, dtype=np.float64)


def write_exr(path, rgb, half=False):
    """Linear RGB as a scanline EXR, ZIP-compressed (lossless), float or half."""
    import numpy as np
    import OpenEXR

    pixels = rgb.astype(np.float16 if half else np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    channels = {c: np.ascontiguousarray(pixels[..., i]) for i, c in enumerate("RGB")}
    with OpenEXR.File(header, channels) as f:
        f.write(path)


def compare(args):
    """RMSE of each image against the first, over all pixels and channels; also
    with values clamped to 1 (what a display shows: the light's edge pixels,
    near 18, weigh less)."""
    import numpy as np

    ref = read_exr(args.reference)
    for path in args.images:
        img = read_exr(path)
        rmse = float(np.sqrt(((img - ref) ** 2).mean()))
        clamped = float(np.sqrt(((np.minimum(img, 1) - np.minimum(ref, 1)) ** 2).mean()))
        print(json.dumps({"image": path, "rmse": rmse, "rmse_clamped": clamped,
                          "mean": float(img.mean()), "reference_mean": float(ref.mean())}))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)

    def render_args(p, seed=True):
        p.add_argument("--spp", type=int, required=True)
        p.add_argument("--threads", type=int, default=os.cpu_count())
        if seed:
            p.add_argument("--seed", type=int, default=0)
        p.add_argument("--out", required=True)

    p = sub.add_parser("mitsuba", help="Mitsuba 3")
    p.add_argument("--variant", choices=["llvm_ad_rgb", "scalar_rgb"], default="llvm_ad_rgb")
    p.add_argument("--sampler", choices=["independent", "multijitter"], default="independent")
    render_args(p)
    p.set_defaults(run=mitsuba)

    p = sub.add_parser("cycles", help="Blender Cycles on the CPU (bpy)")
    render_args(p)
    p.set_defaults(run=cycles)

    p = sub.add_parser("reference", help="the mean of several Mitsuba llvm_ad_rgb passes")
    p.add_argument("--sampler", choices=["independent", "multijitter"], default="multijitter")
    p.add_argument("--passes", type=int, default=16)
    p.add_argument("--half", action="store_true", help="half floats (16-bit)")
    render_args(p, seed=False)
    p.set_defaults(run=reference)

    p = sub.add_parser("compare", help="RMSE of images against a reference")
    p.add_argument("reference")
    p.add_argument("images", nargs="+")
    p.set_defaults(run=compare)

    args = parser.parse_args()
    if "threads" in args:
        confine(args.threads)
    args.run(args)


if __name__ == "__main__":
    main()
