//! The 2D canvas scene (lab section 1): a `[canvas]` table and shapes drawn
//! under 3x3 transforms. A file with a top-level `[canvas]` table is a canvas
//! scene; any other is a 3D scene (see `load_any`).

use crate::diagnostic::Diagnostic;
use crate::model::Color;
use crate::validate::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A point or a vector of the canvas, [x, y]: from -1 to 1 across the
/// image, (0, 0) at its centre, +x to the left, +y up.
pub type Vec2 = [f32; 2];

/// A 2D canvas scene (lab exercise 2): a `canvas` table and the shapes
/// drawn on it, in list order (later shapes over earlier ones).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CanvasFile {
    /// The image: its size, background and gamma. This table makes the file
    /// a 2D canvas scene rather than a 3D one.
    pub canvas: Canvas,
    /// The shapes, drawn in list order, each later one over the earlier.
    /// Default: none (the background alone).
    #[serde(default)]
    pub shapes: Vec<CanvasShape>,
    /// The JSON Schema an editor checks a JSON canvas against (TOML files
    /// use a `#:schema` comment instead). The tracer ignores it.
    #[serde(rename = "$schema", default, skip_serializing_if = "Option::is_none")]
    #[schemars(example = "./schema.json")]
    pub schema: Option<String>,
}

/// The canvas image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Canvas {
    /// Image width in pixels; the canvas's x runs from 1 at the left edge to
    /// -1 at the right.
    #[serde(default = "default_width")]
    #[schemars(range(min = 1, max = 16384))]
    pub width: u32,
    /// Image height in pixels; y runs from -1 at the bottom to 1 at the top.
    #[serde(default = "default_height")]
    #[schemars(range(min = 1, max = 16384))]
    pub height: u32,
    /// The colour the canvas starts with (linear, channels from 0 to 1);
    /// the lab's template starts it grey 0.1.
    #[serde(default = "default_background")]
    #[schemars(inner(range(min = 0)))]
    pub background: Color,
    /// Display gamma for saving; 1 writes the colours as they are (the lab
    /// saves the robot without gamma).
    #[serde(default = "default_gamma")]
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub gamma: f32,
}

fn default_width() -> u32 {
    500
}
fn default_height() -> u32 {
    400
}
fn default_background() -> Color {
    [0.1, 0.1, 0.1]
}
fn default_gamma() -> f32 {
    1.0
}

/// One step of a transform list: `{ translate = [tx, ty] }`,
/// `{ rotate = degrees }` (about (0, 0)) or `{ scale = [sx, sy] }` (or
/// `{ scale = s }`): the 3D list's syntax in two dimensions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
#[schemars(rename = "CanvasTransformStep")]
pub enum Transform {
    /// Move by [x, y] (canvas units; +x is to the left).
    Translate(Vec2),
    /// Turn by this many degrees about (0, 0); with +x on the left, a
    /// positive angle turns clockwise on the screen.
    Rotate(f32),
    /// One factor for both axes, or [x, y], one per axis.
    Scale(Scale2),
}

/// A 2D scale: one factor for both axes, or one per axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "a number (one factor for both axes) or [x, y] (one per axis)"
)]
pub enum Scale2 {
    Uniform(f32),
    PerAxis(Vec2),
}

impl Scale2 {
    pub fn per_axis(self) -> Vec2 {
        match self {
            Scale2::Uniform(s) => [s; 2],
            Scale2::PerAxis(v) => v,
        }
    }
}

/// A circle given by its centre and radius in canvas units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Circle {
    /// The centre, [x, y]; default [0, 0], the canvas's centre.
    #[serde(default)]
    pub center: Vec2,
    /// Above 0, in canvas units: a radius r is r / 2 * width pixels.
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub radius: f32,
}

/// The unit square, corners (+-1, +-1); it takes no parameters (`square = {}`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UnitSquare {}

/// One entry of `shapes`: exactly one of `line`, `circle`, `square`,
/// `polygon`, `group`, with an optional colour, fill and transform list.
/// The transform list composes like the lab's matrix product: `[A, B, C]` is
/// `M = A * B * C`, so the last entry acts on the shape first.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CanvasShape {
    /// A line segment between two points [[x1, y1], [x2, y2]], 2 pixels thick.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line: Option<[Vec2; 2]>,
    /// A circle: `{ center = [x, y], radius = r }`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circle: Option<Circle>,
    /// The unit square, corners (+-1, +-1): `square = {}`; its `transform`
    /// gives it a size and place.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub square: Option<UnitSquare>,
    /// A closed polygon through these points [x, y], in order (at least 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(length(min = 3))]
    pub polygon: Option<Vec<Vec2>>,
    /// Shapes drawn under this entry's transform (and colour, as their default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<Vec<CanvasShape>>,
    /// The shape's colour (linear, channels from 0 to 1). Default: the
    /// enclosing group's colour, or white.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(inner(range(min = 0)))]
    pub color: Option<Color>,
    /// Fill the inside of a circle, square or polygon instead of drawing its
    /// 2-pixel outline; not for a line or a group. Default false.
    #[serde(default)]
    pub fill: bool,
    /// Where the shape goes: a list of steps `[{ translate = [x, y] },
    /// { rotate = degrees }, { scale = [x, y] }]`, the lab's matrix
    /// product (the last step acts first). Default: none, the shape as written.
    #[serde(default)]
    pub transform: Vec<Transform>,
}

/// A canvas shape's kind, once validation has made sure there is exactly one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CanvasShapeRef<'a> {
    Line(&'a [Vec2; 2]),
    Circle(&'a Circle),
    Square,
    Polygon(&'a [Vec2]),
    Group(&'a [CanvasShape]),
}

impl CanvasShape {
    /// All shape keys that are set, in declaration order.
    pub fn kinds(&self) -> Vec<CanvasShapeRef<'_>> {
        let mut kinds = Vec::new();
        if let Some(l) = &self.line {
            kinds.push(CanvasShapeRef::Line(l));
        }
        if let Some(c) = &self.circle {
            kinds.push(CanvasShapeRef::Circle(c));
        }
        if self.square.is_some() {
            kinds.push(CanvasShapeRef::Square);
        }
        if let Some(p) = &self.polygon {
            kinds.push(CanvasShapeRef::Polygon(p));
        }
        if let Some(g) = &self.group {
            kinds.push(CanvasShapeRef::Group(g));
        }
        kinds
    }
}

const SHAPE_KEYS: &str = "`line`, `circle`, `square`, `polygon`, `group`";
/// Groups nest; deeper than this is surely a mistake (and guards the stack).
pub const MAX_GROUP_DEPTH: usize = 32;

/// All problems found in `file`, in file order.
pub fn validate(file: &CanvasFile) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let c = &file.canvas;
    check_image_size(&mut out, c.width, c.height);
    check_color(&mut out, "canvas.background", c.background);
    if !(c.gamma.is_finite() && c.gamma > 0.0) {
        out.push(Diagnostic::new(
            "canvas.gamma",
            format!("expected a number > 0, found {}", c.gamma),
        ));
    }
    for (i, shape) in file.shapes.iter().enumerate() {
        check_shape(&mut out, &format!("shapes[{i}]"), shape, 0);
    }
    out
}

fn check_shape(out: &mut Vec<Diagnostic>, path: &str, s: &CanvasShape, depth: usize) {
    match s.kinds().as_slice() {
        [] => out.push(Diagnostic::new(
            path,
            format!("expected a shape: one of {SHAPE_KEYS}"),
        )),
        [kind] => check_kind(out, path, kind, s.fill, depth),
        _ => out.push(Diagnostic::new(
            path,
            format!("expected exactly one shape per entry; found several of {SHAPE_KEYS}"),
        )),
    }
    if let Some(c) = s.color {
        check_color(out, &format!("{path}.color"), c);
    }
    for (k, t) in s.transform.iter().enumerate() {
        let p = format!("{path}.transform[{k}]");
        let finite = match t {
            Transform::Translate(v) => v.iter().all(|x| x.is_finite()),
            Transform::Scale(s) => s.per_axis().iter().all(|x| x.is_finite()),
            Transform::Rotate(a) => a.is_finite(),
        };
        if !finite {
            out.push(Diagnostic::new(
                p,
                format!("expected finite numbers, found {t:?}"),
            ));
        }
    }
}

fn check_kind(
    out: &mut Vec<Diagnostic>,
    path: &str,
    kind: &CanvasShapeRef,
    fill: bool,
    depth: usize,
) {
    let mut finite_points = |key: &str, points: &[Vec2]| {
        if !points.iter().flatten().all(|x| x.is_finite()) {
            out.push(Diagnostic::new(
                format!("{path}.{key}"),
                format!("expected finite numbers, found {points:?}"),
            ));
        }
    };
    match kind {
        CanvasShapeRef::Line(l) => finite_points("line", &l[..]),
        CanvasShapeRef::Circle(c) => {
            finite_points("circle.center", &[c.center]);
            if !(c.radius.is_finite() && c.radius > 0.0) {
                out.push(Diagnostic::new(
                    format!("{path}.circle.radius"),
                    format!("expected a radius > 0, found {}", c.radius),
                ));
            }
        }
        CanvasShapeRef::Square => {}
        CanvasShapeRef::Polygon(p) => {
            finite_points("polygon", p);
            if p.len() < 3 {
                out.push(Diagnostic::new(
                    format!("{path}.polygon"),
                    format!("expected at least 3 points, found {}", p.len()),
                ));
            }
        }
        CanvasShapeRef::Group(shapes) => {
            if fill {
                out.push(Diagnostic::new(
                    format!("{path}.fill"),
                    "`fill` applies to a circle, square or polygon, not to a group; set it on the group's shapes",
                ));
            }
            if depth + 1 >= MAX_GROUP_DEPTH {
                out.push(Diagnostic::new(
                    format!("{path}.group"),
                    format!("expected groups nested at most {MAX_GROUP_DEPTH} deep"),
                ));
                return;
            }
            for (i, s) in shapes.iter().enumerate() {
                check_shape(out, &format!("{path}.group[{i}]"), s, depth + 1);
            }
        }
    }
    if fill && matches!(kind, CanvasShapeRef::Line(_)) {
        out.push(Diagnostic::new(
            format!("{path}.fill"),
            "`fill` applies to a circle, square or polygon, not to a line",
        ));
    }
}

fn check_image_size(out: &mut Vec<Diagnostic>, width: u32, height: u32) {
    for (key, side) in [("canvas.width", width), ("canvas.height", height)] {
        if side == 0 || side > MAX_IMAGE_SIDE {
            out.push(Diagnostic::new(
                key,
                format!("expected 1 to {MAX_IMAGE_SIDE} pixels, found {side}"),
            ));
        }
    }
    if u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS {
        out.push(Diagnostic::new(
            "canvas",
            format!("expected at most {MAX_IMAGE_PIXELS} pixels (2^28), found {width}x{height}"),
        ));
    }
}

fn check_color(out: &mut Vec<Diagnostic>, path: &str, c: Color) {
    if !c.iter().all(|x| x.is_finite() && *x >= 0.0) {
        out.push(Diagnostic::new(
            path,
            format!("expected a colour with finite channels >= 0, found {c:?}"),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> CanvasFile {
        toml::from_str(text).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn a_canvas_with_every_shape_kind_parses() {
        let f = parse(
            r#"
            [canvas]
            width = 200
            [[shapes]]
            line = [[0, 0], [1, 1]]
            color = [1, 0, 0]
            transform = [{ translate = [0.2, 0.1] }, { rotate = 30 }, { scale = [2, 1] }]
            [[shapes]]
            circle = { center = [0.5, 0], radius = 0.1 }
            fill = true
            [[shapes]]
            square = {}
            [[shapes]]
            polygon = [[0, 0], [1, 0], [0, 1]]
            [[shapes]]
            transform = [{ rotate = 90 }, { scale = 0.5 }]
            [[shapes.group]]
            square = {}
            "#,
        );
        assert_eq!((f.canvas.width, f.canvas.height), (200, 400));
        assert_eq!(f.canvas.background, [0.1; 3]);
        assert_eq!(f.canvas.gamma, 1.0);
        assert_eq!(
            f.shapes[0].transform,
            vec![
                Transform::Translate([0.2, 0.1]),
                Transform::Rotate(30.0),
                Transform::Scale(Scale2::PerAxis([2.0, 1.0]))
            ]
        );
        assert!(f.shapes[1].fill);
        // One number scales both axes, as in 3D.
        let half = f.shapes[4].transform[1];
        assert_eq!(half, Transform::Scale(Scale2::Uniform(0.5)));
        let Transform::Scale(s) = half else {
            unreachable!()
        };
        assert_eq!(s.per_axis(), [0.5, 0.5]);
        assert_eq!(f.shapes[4].group.as_ref().unwrap().len(), 1);
        assert!(validate(&f).is_empty(), "{:?}", validate(&f));
    }

    #[test]
    fn problems_are_reported_with_their_key_path() {
        let f = parse(
            r#"
            [canvas]
            width = 0
            [[shapes]]
            color = [1, 0, 0]
            [[shapes]]
            circle = { radius = -1 }
            [[shapes]]
            polygon = [[0, 0], [1, 0]]
            [[shapes]]
            [[shapes.group]]
            line = [[0, 0], [1, 1]]
            square = {}
            "#,
        );
        let paths: Vec<String> = validate(&f)
            .into_iter()
            .map(|d| d.path.to_string())
            .collect();
        assert_eq!(
            paths,
            [
                "canvas.width",
                "shapes[0]",
                "shapes[1].circle.radius",
                "shapes[2].polygon",
                "shapes[3].group[0]"
            ]
        );
    }

    #[test]
    fn an_unknown_transform_is_a_parse_error() {
        let r: Result<CanvasFile, _> =
            toml::from_str("[canvas]\n[[shapes]]\nsquare = {}\ntransform = [{ shear = 1 }]\n");
        assert!(r.is_err());
    }

    #[test]
    fn load_any_tells_a_canvas_from_a_3d_scene() {
        use crate::{load_any_str, Format, SceneKind};
        use std::path::Path;
        let file = Path::new("x.toml");
        let canvas = load_any_str("[canvas]\nwidth = 10\n", Format::Toml, file).unwrap();
        assert!(matches!(canvas, SceneKind::Canvas(c) if c.canvas.width == 10));
        let scene = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";
        let scene = load_any_str(scene, Format::Toml, file).unwrap();
        assert!(matches!(scene, SceneKind::Scene3d(_)));
        let json = load_any_str(r#"{"canvas": {"height": 7}}"#, Format::Json, file).unwrap();
        assert!(matches!(json, SceneKind::Canvas(c) if c.canvas.height == 7));
        let bad = load_any_str("[canvas]\nwidht = 10\n", Format::Toml, file).unwrap_err();
        let message = bad.to_string();
        assert!(message.contains("x.toml:2:1"), "{message}");
        assert!(message.contains("did you mean `width`?"), "{message}");
    }
}
