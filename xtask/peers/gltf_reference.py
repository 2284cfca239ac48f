#!/usr/bin/env python3
"""Depth images of Khronos glTF samples as Blender sees them: each model
imported by Blender's own glTF importer (bpy, `pip install bpy`), each
pixel's ray through its centre cast from Blender's camera (the file's camera
as Blender imports it, or one placed here from the numbers of the case) into
Blender's scene, its distance to the nearest surface written (0 where it
meets nothing). The tracer's `--aov depth` of the same view is compared
with them by crates/pipeline/tests/gltf_depth.rs.

    python3 xtask/peers/gltf_reference.py crates/pipeline/tests/data/gltf_depth.json

(Blender's importer logs to stdout, so the numbers go to the file named.)

Exit status 3 (one line on stderr) when bpy is not installed.
"""

import json
import math
import sys
from pathlib import Path

KHRONOS = Path(__file__).resolve().parents[2] / "scenes" / "khronos"

# Each case: the model, the image size, and the camera: "file" (the
# file's first camera, as the importer makes it) or a placed one, the
# tracer's [camera] keys (right-handed: +x to the image's right).
CASES = [
    {"name": "cameras-perspective", "model": "Cameras.gltf", "size": [64, 64], "camera": "file"},
    {
        "name": "cameras-orthographic", "model": "Cameras.gltf", "size": [64, 64],
        "camera": {"eye": [0.5, 0.5, 3.0], "look_at": [0.5, 0.5, 0.0], "view_width": 2.0},
    },
    {
        "name": "simple-meshes", "model": "SimpleMeshes.gltf", "size": [80, 60],
        "camera": {"eye": [1.2, 0.3, 2.5], "look_at": [0.9, 0.5, 0.0], "fov": 70.0},
    },
    {
        "name": "box", "model": "Box.gltf", "size": [80, 60],
        "camera": {"eye": [1.5, 1.1, 2.2], "look_at": [0.0, 0.0, 0.0], "fov": 45.0},
    },
]


def blender_point(p):
    """A point of glTF's space (+Y up) in Blender's (+Z up), as its
    importer converts them: (x, -z, y)."""
    x, y, z = p
    return (x, -z, y)


def camera_placed(bpy, mathutils, case):
    """A Blender camera at the case's eye, its -Z toward look_at, its +Y
    up (glTF's +Y, Blender's +Z)."""
    c = case["camera"]
    data = bpy.data.cameras.new("reference")
    obj = bpy.data.objects.new("reference", data)
    bpy.context.scene.collection.objects.link(obj)
    eye = mathutils.Vector(blender_point(c["eye"]))
    forward = (mathutils.Vector(blender_point(c["look_at"])) - eye).normalized()
    obj.matrix_world = mathutils.Matrix.Translation(eye) @ forward.to_track_quat("-Z", "Y").to_matrix().to_4x4()
    data.sensor_fit = "HORIZONTAL"
    if "view_width" in c:
        data.type = "ORTHO"
        data.ortho_scale = c["view_width"]
    else:
        data.angle = math.radians(c["fov"])
    return obj


def depth(bpy, mathutils, case):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.import_scene.gltf(filepath=str(KHRONOS / case["model"]))
    if case["camera"] == "file":
        cameras = sorted((o for o in scene.objects if o.type == "CAMERA"), key=lambda o: o.name)
        camera = cameras[0]
    else:
        camera = camera_placed(bpy, mathutils, case)
    width, height = case["size"]
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.camera = camera
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    # The view frame's corners in the camera's space (top right, bottom
    # right, bottom left, top left), at the image's aspect.
    frame = [camera.matrix_world @ v for v in camera.data.view_frame(scene=scene)]
    top_right, bottom_right, bottom_left, top_left = frame
    eye = camera.matrix_world.translation
    forward = (camera.matrix_world.to_3x3() @ mathutils.Vector((0, 0, -1))).normalized()
    ortho = camera.data.type == "ORTHO"
    values = []
    for j in range(height):
        for i in range(width):
            u, v = (i + 0.5) / width, (j + 0.5) / height
            top = top_left.lerp(top_right, u)
            bottom = bottom_left.lerp(bottom_right, u)
            point = top.lerp(bottom, v)
            if ortho:
                # The frame lies at the clip start: its points on the plane
                # through the eye are the rays' origins.
                origin = point - forward * forward.dot(point - eye)
                direction = forward
            else:
                origin, direction = eye, (point - eye).normalized()
            hit, location, *_ = scene.ray_cast(depsgraph, origin, direction)
            values.append(round((location - origin).length, 6) if hit else 0.0)
    camera_numbers = {
        "eye": list(eye),
        "forward": list(forward),
        "type": camera.data.type,
    }
    return {"size": case["size"], "camera": case["camera"], "blender_camera": camera_numbers, "depth": values}


def main():
    try:
        import bpy
        import mathutils
    except ImportError:
        print("bpy is not installed (pip install bpy)", file=sys.stderr)
        sys.exit(3)
    if len(sys.argv) != 2:
        print("usage: gltf_reference.py OUT.json", file=sys.stderr)
        sys.exit(2)
    out = {"blender": bpy.app.version_string}
    for case in CASES:
        out[case["name"]] = {"model": case["model"], **depth(bpy, mathutils, case)}
    with open(sys.argv[1], "w") as f:
        json.dump(out, f, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
