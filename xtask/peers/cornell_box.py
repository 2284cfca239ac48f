"""Mitsuba 3's `cornell_box()` scene as plain data, shared by the peers.

Running it prints `scenes/cornell-box.toml`:

    python3 xtask/peers/cornell_box.py > scenes/cornell-box.toml

The shapes are written as Mitsuba builds them (`translate * rotate * scale`
of a rectangle [-1, 1]^2 at z = 0 facing +z, or of a cube [-1, 1]^3), so the
numbers come from the same construction rather than from float32 matrices
(whose cos(90 deg) is 4.4e-8). `check_against_mitsuba()` compares them with
the matrices of the installed Mitsuba. Pure Python: Cycles uses it too, and
must not need Mitsuba or numpy.
"""

import math
import sys

# Linear Rec.709 (Mitsuba's `rgb`).
ALBEDO = {
    "white": (0.885809, 0.698859, 0.666422),
    "green": (0.105421, 0.37798, 0.076425),
    "red": (0.570068, 0.0430135, 0.0443706),
}
LIGHT_RADIANCE = (18.387, 13.9873, 6.75357)

# name: (kind, material, translate, (rotation axis, degrees), scale)
SHAPES = {
    "light": ("rectangle", "white", (0, 0.99, 0.01), ("x", 90), (0.23, 0.19, 0.19)),
    "floor": ("rectangle", "white", (0, -1, 0), ("x", -90), (1, 1, 1)),
    "ceiling": ("rectangle", "white", (0, 1, 0), ("x", 90), (1, 1, 1)),
    "back": ("rectangle", "white", (0, 0, -1), ("x", 0), (1, 1, 1)),
    "green-wall": ("rectangle", "green", (1, 0, 0), ("y", -90), (1, 1, 1)),
    "red-wall": ("rectangle", "red", (-1, 0, 0), ("y", 90), (1, 1, 1)),
    "small-box": ("cube", "white", (0.335, -0.7, 0.38), ("y", -17), (0.3, 0.3, 0.3)),
    "large-box": ("cube", "white", (-0.33, -0.4, -0.28), ("y", 18.25), (0.3, 0.61, 0.3)),
}
EMITTER = "light"

# The sensor: look_at(origin, target, up); the fov is on the smaller axis,
# and the image is square.
CAMERA = {"eye": (0, 0, 3.9), "target": (0, 0, 0), "up": (0, 1, 0), "fov": 39.3077}
SIZE = 256
# Mitsuba's `max_depth` (path segments; 8 in cornell_box()).
MITSUBA_MAX_DEPTH = 8


def rotation(axis, degrees):
    """The right-handed (counter-clockwise) rotation, as Mitsuba's and glam's."""
    a = math.radians(degrees)
    # Exact zeros and ones at multiples of 90 degrees, so the TOML is clean.
    c, s = round(math.cos(a), 15), round(math.sin(a), 15)
    if axis == "x":
        return ((1, 0, 0), (0, c, -s), (0, s, c))
    if axis == "y":
        return ((c, 0, s), (0, 1, 0), (-s, 0, c))
    return ((c, -s, 0), (s, c, 0), (0, 0, 1))


def matrix(name):
    """The shape's to_world as a 3x4 matrix (rows), `T * R * S`."""
    _, _, t, (axis, deg), s = SHAPES[name]
    r = rotation(axis, deg)
    return [[r[i][j] * s[j] for j in range(3)] + [t[i]] for i in range(3)]


def apply(m, v, w):
    """m times (v, w): w = 1 for a point, 0 for a direction."""
    return tuple(sum(m[i][j] * v[j] for j in range(3)) + m[i][3] * w for i in range(3))


def quad(name):
    """A rectangle as corner, edge_u, edge_v (edge_u x edge_v is its normal)."""
    m = matrix(name)
    return apply(m, (-1, -1, 0), 1), apply(m, (2, 0, 0), 0), apply(m, (0, 2, 0), 0)


def camera_frame():
    """Mitsuba's look_at: the columns (left, up, forward) of the sensor's to_world."""
    eye, target, up = (CAMERA[k] for k in ("eye", "target", "up"))
    fwd = normalize(sub(target, eye))
    left = normalize(cross(up, fwd))
    return left, cross(fwd, left), fwd


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def check_against_mitsuba(tolerance=1e-6):
    """Raises if the data above differs from the installed Mitsuba's cornell_box()."""
    import mitsuba as mi

    if not mi.variant():
        mi.set_variant("scalar_rgb")
    box = mi.cornell_box()
    shapes = {k for k, v in box.items() if isinstance(v, dict) and "to_world" in v}
    assert shapes - {"sensor"} == set(SHAPES), shapes
    for name in SHAPES:
        theirs = box[name]["to_world"].matrix
        ours = matrix(name)
        for i in range(3):
            for j in range(4):
                assert abs(theirs[i, j] - ours[i][j]) < tolerance, (name, i, j)
        assert box[name]["type"] == SHAPES[name][0], name
        assert box[name]["bsdf"]["id"] == SHAPES[name][1], name
    for key, rgb in ALBEDO.items():
        assert tuple(box[key]["reflectance"]["value"]) == rgb, key
    assert tuple(box[EMITTER]["emitter"]["radiance"]["value"]) == LIGHT_RADIANCE
    sensor = box["sensor"]
    frame = camera_frame() + (CAMERA["eye"],)
    for j, col in enumerate(frame):
        for i in range(3):
            assert abs(sensor["to_world"].matrix[i, j] - col[i]) < tolerance, ("sensor", i, j)
    assert sensor["fov"] == CAMERA["fov"] and sensor["fov_axis"] == "smaller"
    assert sensor["film"]["width"] == sensor["film"]["height"] == SIZE
    assert box["integrator"]["max_depth"] == MITSUBA_MAX_DEPTH


def fmt(v):
    """A vector in TOML, each number rounded to 9 places (f32 keeps fewer)."""
    def num(x):
        x = round(x, 9) + 0.0  # + 0.0 turns -0.0 into 0.0
        return str(int(x)) if x == int(x) else repr(x)

    return "[" + ", ".join(num(x) for x in v) + "]"


def toml():
    eye, target, up = (CAMERA[k] for k in ("eye", "target", "up"))
    fwd = camera_frame()[2]
    # The point of the view line nearest the origin: any point on it would do.
    look_at = tuple(e + f * -sum(a * b for a, b in zip(eye, fwd)) for e, f in zip(eye, fwd))
    out = [
        "# The Cornell box of Mitsuba 3 (`mitsuba.cornell_box()`), path traced: the",
        "# ceiling's lamp is the only light, and everything else is lit by what the",
        "# walls and boxes reflect. The red and green walls tint the boxes' sides",
        "# facing them, and the image agrees with Mitsuba's own render of the scene",
        "# (crates/tracer-core/tests/cornell_box.rs).",
        "#",
        "# Made by `python3 xtask/peers/cornell_box.py > scenes/cornell-box.toml` from",
        "# Mitsuba 3.9's to_world transforms (its rectangles are [-1, 1]^2 at z = 0",
        "# facing +z, its cubes [-1, 1]^3), with a box pixel filter instead of its",
        "# Gaussian. Mitsuba's max_depth 8 is max_depth 7 here.",
        "[camera]",
        f"eye = {fmt(eye)}",
        f"look_at = {fmt(look_at)}",
        f"up = {fmt(camera_frame()[1])}",
        f"fov = {CAMERA['fov']}           # the image is square: Mitsuba's fov on its smaller axis",
        f"width = {SIZE}",
        f"height = {SIZE}",
        'handedness = "right"   # +x to the right: the red wall (x = -1) on the left',
        "",
        "[render]",
        'integrator = "path"',
        f"max_depth = {MITSUBA_MAX_DEPTH - 1}",
        "samples = 64",
        "gamma = 2.2",
        'saturation = "clamp"',
        "",
    ]
    for name, rgb in ALBEDO.items():
        out += [f"[materials.{name}]", f"diffuse = {fmt(rgb)}", ""]
    out += [
        "# The light reflects as the white walls do, and emits along its normal only.",
        "[materials.light]",
        f"diffuse = {fmt(ALBEDO['white'])}",
        f"emission = {fmt(LIGHT_RADIANCE)}",
        "",
    ]
    for name, (kind, material, t, (axis, deg), s) in SHAPES.items():
        out.append(f"# {name}")
        out.append("[[objects]]")
        if kind == "rectangle":
            corner, eu, ev = quad(name)
            out.append(f"quad = {{ corner = {fmt(corner)}, edge_u = {fmt(eu)}, edge_v = {fmt(ev)} }}")
        else:
            rotate = tuple(deg if a == axis else 0 for a in "xyz")
            out.append("box = { min = [-1, -1, -1], max = [1, 1, 1] }")
            out.append(
                f"transform = {{ scale = {fmt(s)}, rotate = {fmt(rotate)}, translate = {fmt(t)} }}"
            )
        out.append(f'material = "{"light" if name == EMITTER else material}"')
        out.append("")
    return "\n".join(out).rstrip() + "\n"


if __name__ == "__main__":
    if "--check" in sys.argv:
        check_against_mitsuba()
        print("cornell_box.py matches mitsuba.cornell_box()", file=sys.stderr)
    sys.stdout.write(toml())
