//! Problems are reported in the order they stand in the file, whatever the
//! order of the keys in the model (materials are a sorted map, lights come
//! before objects there).

use scene_format::{Format, SceneError};
use std::path::Path;

#[test]
fn problems_come_in_file_order() {
    // Objects first, then material `zz` before `aa`, then a light: each
    // with one bad value, on lines 5, 8, 10 and 13.
    let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                [[objects]]\nsphere = { center = [0, 0, 0], radius = -1 }\nmaterial = \"zz\"\n\
                [materials.zz]\ndiffuse = [-1, 0, 0]\n\
                [materials.aa]\nambient = [-2, 0, 0]\n\
                [[lights]]\nposition = [0, 0, 5]\ncolor = [-1, 0, 0]\n";
    let error = scene_format::load_str(text, Format::Toml, Path::new("o.toml")).unwrap_err();
    assert!(matches!(error, SceneError::Invalid { .. }), "{error}");
    let lines: Vec<usize> = error
        .diagnostics()
        .iter()
        .map(|d| d.location.expect("located").line)
        .collect();
    assert_eq!(lines, [5, 8, 10, 13]);
    let paths: Vec<String> = error
        .diagnostics()
        .iter()
        .map(|d| d.path.to_string())
        .collect();
    assert_eq!(
        paths,
        [
            "objects[0].sphere.radius",
            "materials.zz.diffuse",
            "materials.aa.ambient",
            "lights[0].color"
        ]
    );
}
