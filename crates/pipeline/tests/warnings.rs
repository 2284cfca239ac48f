//! A scene's warnings as shown: the line `tracer render` prints, and the
//! place of each in the file that holds it.

use std::path::Path;
use tracer_pipeline::{load, Input, Options};

#[test]
fn every_warning_is_placed_in_its_file_in_one_reading_of_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = "include = [\"lib.toml\"]\n[camera]\neye = [0, 0, 10]\n\
                     look_at = [0, 0, 0]\n[[lights]]\nposition = [0, 5, 5]\n"
        .to_string();
    // 20000 warnings: placed one file reading each, not one per warning
    // (which took minutes).
    for i in 0..20_000 {
        scene += &format!(
            "[[objects]]\nsphere = {{ center = [{i}, 0, 0], radius = 0.1 }}\n\
             material = {{ diffuse = [200, 10, 10] }}\n"
        );
    }
    std::fs::write(dir.path().join("s.toml"), &scene).unwrap();
    std::fs::write(
        dir.path().join("lib.toml"),
        "# a library\n[materials.red]\ndiffuse = [255, 0, 0]\n",
    )
    .unwrap();
    let path = dir.path().join("s.toml");
    let loaded = load(&Input::File(path.clone())).unwrap();
    let start = std::time::Instant::now();
    let list = loaded.warning_list(&Options::default());
    assert!(start.elapsed().as_secs() < 20, "{:?}", start.elapsed());
    let of = |key: &str| {
        list.iter()
            .find(|w| w.key == key)
            .unwrap_or_else(|| panic!("{key}"))
    };
    // The last object's colour, at its line of the scene file.
    let last = of("objects[19999].material.diffuse");
    let line = scene.lines().count();
    assert_eq!(last.location.map(|l| l.line), Some(line));
    assert_eq!(last.file, path);
    assert!(
        last.text.ends_with("colours run from 0 to 1, not 0 to 255"),
        "{}",
        last.text
    );
    // The library's material, in the library, at its own line.
    let red = of("materials.red.diffuse");
    assert_eq!(red.file, Path::new(&dir.path().join("lib.toml")));
    assert_eq!(red.location.map(|l| l.line), Some(3));
    assert!(red.text.starts_with(&format!(
        "warning: {}: `materials.red.diffuse`",
        red.file.display()
    )));
}

#[test]
fn the_warnings_are_those_of_the_scene_as_the_options_change_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lens.toml");
    let scene = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\naperture = 0.2\n\
                 [render]\nsamples = 64\n[[lights]]\nposition = [0, 5, 5]\n\
                 [materials.m]\nambient = [0.1, 0.1, 0.1]\n\
                 [[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\nmaterial = \"m\"\n";
    std::fs::write(&path, scene).unwrap();
    let loaded = load(&Input::File(path)).unwrap();
    let keys = |options: &Options| -> Vec<String> {
        let list = loaded.warnings_for(options);
        list.into_iter().map(|d| d.path.to_string()).collect()
    };
    assert!(keys(&Options::default()).is_empty());
    // Four samples through a lens are grainy; the path tracer reads no ambient.
    let few = Options {
        samples: Some(4),
        ..Options::default()
    };
    assert_eq!(keys(&few), ["render.samples"]);
    let path_mode = Options {
        integrator: Some(scene_format::Integrator::Path),
        ..Options::default()
    };
    assert_eq!(keys(&path_mode), ["materials.m.ambient"]);
}
