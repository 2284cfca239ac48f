//! `cargo xtask gallery`: docs/src/gallery.md is current, shows every scene and
//! every golden, and each command is one `tracer` accepts.

use std::path::{Path, PathBuf};
use xtask::gallery;

fn root() -> PathBuf {
    xtask::workspace_root()
}

fn committed() -> String {
    std::fs::read_to_string(root().join(gallery::GALLERY)).unwrap_or_default()
}

#[test]
fn the_committed_gallery_is_current() {
    let current = gallery::render(&root()).unwrap();
    assert!(
        committed() == current,
        "docs/src/gallery.md is stale: run cargo xtask gallery"
    );
}

/// The scene files, found by a walk of this test's own: `scenes/...toml`.
fn scene_files(dir: &Path, out: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            scene_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "toml") {
            let rel = path.strip_prefix(root()).unwrap();
            out.push(rel.to_str().unwrap().replace('\\', "/"));
        }
    }
}

/// The targets of the gallery's thumbnails, `<img src="target" ..>`; each
/// is linked to the same image at its full size.
fn image_links(text: &str) -> Vec<&str> {
    text.split("<img src=\"")
        .skip(1)
        .filter_map(|rest| rest.split_once('"'))
        .map(|(target, _)| target)
        .inspect(|target| {
            assert!(text.contains(&format!("<a href=\"{target}\"><img src=\"{target}\"")))
        })
        .collect()
}

/// The commands of the gallery's `sh` blocks.
fn commands(text: &str) -> Vec<&str> {
    text.split("```sh\n")
        .skip(1)
        .filter_map(|rest| rest.split_once("\n```"))
        .map(|(command, _)| command)
        .collect()
}

#[test]
fn every_scene_and_every_golden_is_in_the_gallery_with_its_command() {
    let text = committed();
    let mut scenes = Vec::new();
    scene_files(&root().join("scenes"), &mut scenes);
    assert!(scenes.contains(&"scenes/bench/bunny.toml".to_string()));
    for scene in &scenes {
        assert!(
            text.contains(&format!("### `{scene}`\n")),
            "{scene}: heading"
        );
        assert!(
            text.contains(&format!("```sh\ntracer render {scene} -o ")),
            "{scene}: command"
        );
    }
    // Every link opens a golden from docs/src/, and every golden is linked once.
    let links = image_links(&text);
    let docs = root().join("docs/src");
    for link in &links {
        assert!(link.starts_with("../../golden/"), "{link}");
        assert!(docs.join(link).is_file(), "{link} does not open");
    }
    let goldens: Vec<String> = std::fs::read_dir(root().join("golden"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|name| name.ends_with(".png"))
        .collect();
    assert_eq!(links.len(), goldens.len(), "{links:?}");
    for name in &goldens {
        let link = format!("../../golden/{name}");
        assert_eq!(links.iter().filter(|l| **l == link).count(), 1, "{name}");
    }
    // Every scene has a golden: none is listed as missing.
    assert!(!text.contains("No golden yet"));
}

/// Each command, split into words, parses with the `tracer` binary's own
/// clap definition, and names as its output the image shown below it.
#[test]
fn every_command_is_one_tracer_accepts() {
    let text = committed();
    let all = commands(&text);
    assert!(all.len() >= 29, "{} commands", all.len());
    for command in &all {
        let words: Vec<&str> = command.split_whitespace().collect();
        assert_eq!(words[0], "tracer", "{command}");
        if let Err(e) = tracer_cli::command().try_get_matches_from(&words) {
            panic!("{command}: {e}");
        }
    }
    for block in text.split("\n### ").skip(1) {
        let command = commands(block)[0];
        let output = command
            .split_whitespace()
            .skip_while(|w| !matches!(*w, "-o" | "--plot"))
            .nth(1)
            .unwrap_or_else(|| panic!("{command}: no output named"));
        assert_eq!(
            image_links(block),
            [format!("../../golden/{output}")],
            "{command}"
        );
    }
}

#[test]
fn a_scene_without_a_golden_is_listed_as_such() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("scenes/more")).unwrap();
    std::fs::create_dir_all(dir.path().join("golden")).unwrap();
    std::fs::write(dir.path().join("scenes/a.toml"), "# A ball.\n[camera]\n").unwrap();
    std::fs::write(dir.path().join("scenes/more/b.toml"), "[camera]\n").unwrap();
    std::fs::write(dir.path().join("golden/a.png"), b"").unwrap();
    let text = gallery::render(dir.path()).unwrap();
    assert!(text.contains("### `scenes/a.toml`\n\nA ball.\n\n```sh\ntracer render scenes/a.toml -o a.png\n```\n\n<a href=\"../../golden/a.png\"><img src=\"../../golden/a.png\" alt=\"a\" width=\"400\"></a>\n"), "{text}");
    assert!(
        text.contains("```sh\ntracer render scenes/more/b.toml -o more-b.png\n```\n\nNo golden yet: look at the render, then `cargo xtask golden --bless more-b`.\n"),
        "{text}"
    );
}

#[test]
fn a_caption_is_the_first_comment_paragraph() {
    let text = "#:schema ../schema.json\n# Lab table 1.9:\n# reflectance\n#\n# More.\n[camera]\n";
    assert_eq!(gallery::caption(text), "Lab table 1.9: reflectance");
    assert_eq!(gallery::caption("[camera]\n# late\n"), "");
}
