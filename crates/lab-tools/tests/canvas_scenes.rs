//! The lab's 2D canvas scenes in `scenes/`, drawn and checked against
//! positions worked out by hand from the template's pixel mapping.

use glam::Vec3;
use lab_tools::canvas::{draw, encoding};
use scene_format::{CanvasFile, SceneKind};
use std::path::Path;

fn load(name: &str) -> CanvasFile {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    match scene_format::load_any(&path).unwrap_or_else(|e| panic!("{e}")) {
        SceneKind::Canvas(file) => file,
        SceneKind::Scene3d(_) => panic!("{name} is not a canvas scene"),
    }
}

#[test]
fn the_robot_has_head_body_arms_and_legs_on_the_template_grey() {
    let file = load("robot.toml");
    assert_eq!(
        encoding(&file).gamma,
        1.0,
        "the lab saves the robot without gamma"
    );
    let image = draw(&file);
    assert_eq!((image.width, image.height), (500, 400));
    assert_eq!(image.get(0, 0), Vec3::splat(0.1));
    let colour_at = |i, j| image.get(i, j);
    // Head: the square's top edge y = 0.6 + 0.2 = 0.8 is row 400 * 0.2 / 2 = 40,
    // drawn on rows 39 and 40, at the centre column 250.
    let yellow = Vec3::new(0.9, 0.9, 0.2);
    assert_eq!(colour_at(250, 39), yellow);
    assert_eq!(colour_at(250, 40), yellow);
    // Body: the right edge x = -0.25 is column 500 * 1.25 / 2 = 312.5,
    // drawn on columns 312 and 313 (centres within [-1, 1) of 312.5).
    let blue = Vec3::new(0.2, 0.6, 1.0);
    assert_eq!(colour_at(312, 200), blue);
    assert_eq!(colour_at(313, 200), blue);
    // Arms, green, on both sides of the body; legs, orange, below it.
    let count = |colour: Vec3, columns: std::ops::Range<u32>, rows: std::ops::Range<u32>| {
        columns
            .flat_map(|i| rows.clone().map(move |j| (i, j)))
            .filter(|&(i, j)| image.get(i, j) == colour)
            .count()
    };
    let green = Vec3::new(0.3, 0.9, 0.4);
    assert!(count(green, 0..186, 0..400) > 100, "no arm on the left");
    assert!(count(green, 314..500, 0..400) > 100, "no arm on the right");
    let orange = Vec3::new(0.9, 0.5, 0.2);
    assert!(count(orange, 0..250, 265..400) > 100, "no left leg");
    assert!(count(orange, 250..500, 265..400) > 100, "no right leg");
    assert_eq!(count(orange, 0..500, 0..260), 0, "legs above the hips");
}

#[test]
fn the_lab_triangle_and_its_translation() {
    let image = draw(&load("triangle-2d.toml"));
    let red = Vec3::new(1.0, 0.0, 0.0);
    let green = Vec3::new(0.0, 1.0, 0.0);
    // The edge from (0.4, 0.3) to (-0.4, 0.3): row 400 * 0.7 / 2 = 140, drawn
    // on rows 139 and 140, from column 150 to 350.
    for i in [150, 250, 349] {
        assert_eq!(image.get(i, 139), red, "column {i}");
        assert_eq!(image.get(i, 140), red, "column {i}");
        assert_eq!(image.get(i, 138), Vec3::splat(0.1), "column {i}");
    }
    // Translated by (0.2, 0.1): 50 columns to the left, 20 rows up.
    for i in [100, 200, 299] {
        assert_eq!(image.get(i, 119), green, "column {i}");
        assert_eq!(image.get(i, 120), green, "column {i}");
    }
}
