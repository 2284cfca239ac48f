//! The lab's 2D canvas (lab section 1 and the template's `drawLine` and
//! `drawCircle`, section 7): points in [-1, 1]^2 with (0, 0) at the centre,
//! +y up and, like the 3D camera, +x to the LEFT; homogeneous 3x3 transforms.
//!
//! Every shape is rasterised by testing pixel centres, so what a pixel gets
//! never depends on the order of a line's end points.

mod raster;
mod transform;

pub use raster::{Canvas, LINE_WIDTH};
pub use transform::{apply, compose, matrix, rotation, scale, translation};

use glam::{Mat3, Vec2, Vec3};
use scene_format::canvas::{CanvasFile, CanvasShape, CanvasShapeRef};
use tracer_core::image::{Encoding, LinearImage, Saturation};

/// The unit square's corners, (+-1, +-1), in drawing order.
const UNIT_SQUARE: [Vec2; 4] = [
    Vec2::new(1.0, 1.0),
    Vec2::new(-1.0, 1.0),
    Vec2::new(-1.0, -1.0),
    Vec2::new(1.0, -1.0),
];

/// Draws a canvas scene file: the background, then every shape in file order.
pub fn draw(file: &CanvasFile) -> LinearImage {
    let c = &file.canvas;
    let mut canvas = Canvas::new(c.width, c.height, c.background.into());
    for shape in &file.shapes {
        draw_shape(&mut canvas, shape, &Mat3::IDENTITY, Vec3::ONE);
    }
    canvas.image
}

/// How a canvas scene is saved: its gamma (the lab saves the robot without,
/// the default 1), each channel clamped.
pub fn encoding(file: &CanvasFile) -> Encoding {
    Encoding {
        gamma: file.canvas.gamma,
        saturation: Saturation::Clamp,
    }
}

fn draw_shape(canvas: &mut Canvas, shape: &CanvasShape, parent: &Mat3, parent_colour: Vec3) {
    let m = *parent * compose(&shape.transform);
    let colour = shape.color.map_or(parent_colour, Vec3::from);
    let points =
        |ps: &[[f32; 2]]| -> Vec<Vec2> { ps.iter().map(|&p| apply(&m, Vec2::from(p))).collect() };
    // Validation leaves exactly one kind; anything else draws nothing.
    let kinds = shape.kinds();
    let [kind] = kinds.as_slice() else {
        return;
    };
    match kind {
        CanvasShapeRef::Line([a, b]) => {
            canvas.draw_line(apply(&m, (*a).into()), apply(&m, (*b).into()), colour)
        }
        CanvasShapeRef::Circle(circle) => {
            // A circle stays round: its radius takes the transform's mean scale.
            let scale = m.determinant().abs().sqrt();
            let centre = apply(&m, circle.center.into());
            canvas.draw_circle(centre, circle.radius * scale, colour, shape.fill)
        }
        CanvasShapeRef::Square => {
            let corners: Vec<Vec2> = UNIT_SQUARE.iter().map(|&p| apply(&m, p)).collect();
            canvas.draw_polygon(&corners, colour, shape.fill)
        }
        CanvasShapeRef::Polygon(ps) => canvas.draw_polygon(&points(ps), colour, shape.fill),
        CanvasShapeRef::Group(shapes) => {
            for s in shapes.iter() {
                draw_shape(canvas, s, &m, colour);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene_format::canvas::Transform;
    use std::collections::BTreeSet;

    const RED: Vec3 = Vec3::new(1.0, 0.0, 0.0);

    fn close(a: Vec2, b: Vec2) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    /// The set of pixels that differ from the background.
    /// A 100x100 black canvas, linear, holding `shapes`.
    fn black_100x100(shapes: Vec<CanvasShape>) -> CanvasFile {
        CanvasFile {
            canvas: scene_format::canvas::Canvas {
                width: 100,
                height: 100,
                background: [0.0; 3],
                gamma: 1.0,
            },
            shapes,
            schema: None,
        }
    }

    fn painted(canvas: &Canvas) -> BTreeSet<(u32, u32)> {
        let img = &canvas.image;
        let bg = Vec3::ZERO;
        (0..img.height)
            .flat_map(|j| (0..img.width).map(move |i| (i, j)))
            .filter(|&(i, j)| img.get(i, j) != bg)
            .collect()
    }

    #[test]
    fn x_plus_one_maps_to_column_zero_and_y_plus_one_to_row_zero() {
        let canvas = Canvas::new(500, 400, Vec3::ZERO);
        assert_eq!(canvas.pixel_of(Vec2::new(1.0, 1.0)), (0, 0));
        // (0, 0) is the centre: W/2, H/2.
        assert_eq!(canvas.pixel_of(Vec2::ZERO), (250, 200));
        // x = -1 is the right edge, one past the last column.
        assert_eq!(canvas.pixel_of(Vec2::new(-1.0, -1.0)), (500, 400));
        // x = 0.5 is a quarter of the width from the left: 500 - 1.5 / 2 * 500.
        assert_eq!(canvas.pixel_of(Vec2::new(0.5, 0.0)), (125, 200));
    }

    #[test]
    fn the_matrices_are_the_labs() {
        let t = translation(0.2, 0.1);
        assert!(close(apply(&t, Vec2::new(0.4, 0.3)), Vec2::new(0.6, 0.4)));
        let r = rotation(90.0);
        assert!(close(apply(&r, Vec2::new(1.0, 0.0)), Vec2::new(0.0, 1.0)));
        let s = scale(2.0, 3.0);
        assert!(close(apply(&s, Vec2::new(1.0, 1.0)), Vec2::new(2.0, 3.0)));
        // The lab's GLM matrix {{1,0,0}, {0,1,0}, {tX,tY,1}} lists columns.
        assert_eq!(t.col(2), Vec3::new(0.2, 0.1, 1.0));
    }

    #[test]
    fn a_translation_moves_a_drawn_point_by_the_right_number_of_pixels() {
        let mut before = Canvas::new(500, 400, Vec3::ZERO);
        before.draw_circle(Vec2::new(0.1, -0.2), 0.02, RED, true);
        let mut after = Canvas::new(500, 400, Vec3::ZERO);
        let t = translation(0.2, 0.1);
        after.draw_circle(apply(&t, Vec2::new(0.1, -0.2)), 0.02, RED, true);
        // +0.2 in x is 0.2 / 2 * 500 = 50 columns to the LEFT; +0.1 in y is
        // 0.1 / 2 * 400 = 20 rows up.
        let moved: BTreeSet<(u32, u32)> = painted(&before)
            .iter()
            .map(|&(i, j)| (i - 50, j - 20))
            .collect();
        assert!(!moved.is_empty());
        // Float rounding may shift an edge pixel; the bulk must coincide.
        let after = painted(&after);
        let common = moved.intersection(&after).count();
        assert!(
            common * 100 >= 95 * moved.len().max(after.len()),
            "{common}"
        );
    }

    #[test]
    fn translating_a_point_on_the_grid_moves_its_pixel_exactly() {
        let canvas = Canvas::new(500, 400, Vec3::ZERO);
        let p = Vec2::new(0.5, 0.5);
        let q = apply(&translation(0.2, 0.1), p);
        let (i0, j0) = canvas.pixel_of(p);
        let (i1, j1) = canvas.pixel_of(q);
        assert_eq!((i0 - i1, j0 - j1), (50, 20));
    }

    #[test]
    fn rotate_then_translate_differs_from_translate_then_rotate() {
        use Transform::{Rotate, Translate};
        let p = Vec2::new(0.5, 0.0);
        // Listed as the lab multiplies: [T, R] is T * R, R acts first.
        let rotate_first = compose(&[Translate([0.2, 0.0]), Rotate(90.0)]);
        let translate_first = compose(&[Rotate(90.0), Translate([0.2, 0.0])]);
        // R(90) (0.5, 0) = (0, 0.5); + (0.2, 0) = (0.2, 0.5).
        assert!(close(apply(&rotate_first, p), Vec2::new(0.2, 0.5)));
        // (0.5, 0) + (0.2, 0) = (0.7, 0); R(90) -> (0, 0.7).
        assert!(close(apply(&translate_first, p), Vec2::new(0.0, 0.7)));
    }

    #[test]
    fn a_horizontal_line_is_two_pixels_thick_either_way_round() {
        let mut a = Canvas::new(100, 100, Vec3::ZERO);
        a.draw_line(Vec2::new(0.5, 0.0), Vec2::new(-0.5, 0.0), RED);
        let mut b = Canvas::new(100, 100, Vec3::ZERO);
        b.draw_line(Vec2::new(-0.5, 0.0), Vec2::new(0.5, 0.0), RED);
        let pixels = painted(&a);
        assert_eq!(pixels, painted(&b));
        // y = 0 is row 50.0 exactly: rows 49 and 50; x from column 25 to 75,
        // grown by one pixel each end: columns 24 to 75.
        let rows: BTreeSet<u32> = pixels.iter().map(|&(_, j)| j).collect();
        assert_eq!(rows, BTreeSet::from([49, 50]));
        let columns: BTreeSet<u32> = pixels.iter().map(|&(i, _)| i).collect();
        assert_eq!(columns, (24..76).collect());
    }

    #[test]
    fn a_circle_radius_is_r_over_2_times_width_pixels() {
        let mut canvas = Canvas::new(200, 100, Vec3::ZERO);
        canvas.draw_circle(Vec2::ZERO, 0.5, RED, false);
        // 0.5 / 2 * 200 = 50 pixels, round even though H != W; centre (100, 50).
        assert_eq!(canvas.image.get(100 + 49, 50), RED);
        assert_eq!(canvas.image.get(100 - 50, 50), RED);
        assert_eq!(canvas.image.get(100, 50 - 50), RED);
        assert_eq!(canvas.image.get(100, 50), Vec3::ZERO);
        assert_eq!(canvas.image.get(100 + 52, 50), Vec3::ZERO);
    }

    #[test]
    fn a_filled_square_under_scale_and_translation_covers_its_box() {
        use Transform::{Scale, Translate};
        let file = black_100x100(vec![CanvasShape {
            square: Some(Default::default()),
            fill: true,
            color: Some([1.0, 0.0, 0.0]),
            transform: vec![
                Translate([0.5, 0.5]),
                Scale(scene_format::canvas::Scale2::Uniform(0.2)),
            ],
            ..Default::default()
        }]);
        let image = draw(&file);
        let canvas = Canvas { image };
        // x in [0.3, 0.7] -> columns 100 - 1.7 * 50 = 15 to 35; likewise rows.
        let expected: BTreeSet<(u32, u32)> = (15..35)
            .flat_map(|i| (15..35).map(move |j| (i, j)))
            .collect();
        assert_eq!(painted(&canvas), expected);
    }

    #[test]
    fn a_group_transform_applies_to_its_shapes_and_colour_is_inherited() {
        use Transform::Translate;
        let child = CanvasShape {
            circle: Some(scene_format::canvas::Circle {
                center: [0.0, 0.0],
                radius: 0.05,
            }),
            fill: true,
            ..Default::default()
        };
        let file = black_100x100(vec![CanvasShape {
            group: Some(vec![child]),
            color: Some([0.0, 1.0, 0.0]),
            transform: vec![Translate([-0.5, 0.0])],
            ..Default::default()
        }]);
        let image = draw(&file);
        // x = -0.5 is column 75; the group's colour is green.
        assert_eq!(image.get(75, 50), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(image.get(50, 50), Vec3::ZERO);
    }
}
