//! The book's scenes and outputs are the tracer's: every fenced `toml` or
//! `json` block of `docs/src` and the README passes `tracer check` (a part
//! of a scene with a camera added), or, when a `$ tracer check NAME` block
//! follows it, prints exactly what that block shows; a block marked
//! `<!-- renders: PICTURE -->` renders to that picture, one marked
//! `<!-- file: PATH -->` is a file the page's later scenes read; a
//! `$ tracer explain` block is what the command prints. Paths in a block
//! are read as from a file of `scenes/`.

mod common;

// The Markdown reader the book's other checks use (`cargo xtask book`).
#[path = "../../../xtask/src/book/markdown.rs"]
#[allow(dead_code)]
mod markdown;

use markdown::Fence;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The book's pages and the README.
fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    walk(&root().join("docs/src"), &mut out);
    out.sort();
    out.push(root().join("README.md"));
    out
}

/// A folder that reads as `scenes/`: a link to each of its entries.
fn scenes_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for entry in std::fs::read_dir(root().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        let link = dir.path().join(path.file_name().unwrap());
        #[cfg(unix)]
        std::os::unix::fs::symlink(&path, &link).unwrap();
        #[cfg(not(unix))]
        let _ = (path, link);
    }
    dir
}

/// The line before the fence, when it is an HTML comment.
fn marker(text: &str, fence: &Fence) -> Option<String> {
    let line = text.lines().nth(fence.line.checked_sub(2)?)?.trim();
    let inner = line.strip_prefix("<!--")?.strip_suffix("-->")?;
    Some(inner.trim().to_string())
}

/// `{{#include FILE}}` lines replaced by the file, as mdBook does.
fn expand_includes(body: &str, page: &Path) -> String {
    body.lines()
        .map(|line| {
            match line
                .trim()
                .strip_prefix("{{#include ")
                .and_then(|l| l.strip_suffix("}}"))
            {
                Some(file) => std::fs::read_to_string(page.parent().unwrap().join(file.trim()))
                    .unwrap_or_else(|e| panic!("{}: {file}: {e}", page.display())),
                None => format!("{line}\n"),
            }
        })
        .collect()
}

/// Whether a block is a whole scene (a 3D scene's camera or a canvas).
fn is_whole(lang: &str, text: &str) -> bool {
    match lang {
        "json" => serde_json::from_str::<serde_json::Value>(text)
            .is_ok_and(|v| v.get("camera").is_some() || v.get("canvas").is_some()),
        _ => text
            .parse::<toml::Table>()
            .is_ok_and(|t| t.contains_key("camera") || t.contains_key("canvas")),
    }
}

/// A part of a scene made whole by a camera, as a file of `scenes/`.
fn with_camera(lang: &str, text: &str) -> String {
    match lang {
        "json" => {
            let mut value: serde_json::Value = serde_json::from_str(text).unwrap_or_default();
            if let Some(map) = value.as_object_mut() {
                map.insert(
                    "camera".into(),
                    serde_json::json!({ "eye": [0, 0, 10], "look_at": [0, 0, 0] }),
                );
            }
            value.to_string()
        }
        _ => format!("{text}\n[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n"),
    }
}

/// What a `$ COMMAND` text block shows: the command and the lines after.
fn shown_output(fence: &Fence, command: &str) -> Option<(String, String)> {
    let (first, rest) = fence.body.split_once('\n')?;
    let args = first.strip_prefix("$ ")?;
    args.starts_with(command)
        .then(|| (args.to_string(), rest.to_string()))
}

fn tracer(dir: &Path, args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    (out.status.success(), text)
}

/// Lines compared without trailing spaces (editors strip them).
fn same_text(a: &str, b: &str) -> bool {
    let lines = |s: &str| -> Vec<String> {
        s.trim_end()
            .lines()
            .map(|l| l.trim_end().to_string())
            .collect()
    };
    lines(a) == lines(b)
}

#[test]
fn every_scene_in_the_book_is_one_the_tracer_accepts() {
    let scenes = scenes_folder();
    let mut problems = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        let fences = markdown::fences(&text);
        for (i, fence) in fences.iter().enumerate() {
            if !matches!(fence.lang.as_str(), "toml" | "json") {
                continue;
            }
            let at = format!(
                "{}:{}",
                page.strip_prefix(root()).unwrap_or(&page).display(),
                fence.line
            );
            let body = expand_includes(&fence.body, &page);
            let whole = is_whole(&fence.lang, &body);
            let mark = marker(&text, fence);
            if mark.as_deref().is_some_and(|m| m.starts_with("unchecked")) {
                if whole {
                    problems.push(format!("{at}: a whole scene is always checked"));
                }
                continue;
            }
            let expected = fences
                .get(i + 1)
                .filter(|f| f.lang == "text")
                .and_then(|f| shown_output(f, "tracer check "));
            let name = match &expected {
                Some((command, _)) => command["tracer check ".len()..].trim().to_string(),
                None => format!("block.{}", fence.lang),
            };
            // A file the page's later scenes read: kept, as it is, at its path.
            let kept = mark
                .as_deref()
                .and_then(|m| m.strip_prefix("file:"))
                .map(str::trim);
            let name = kept.map_or(name, str::to_string);
            let file = if whole || kept.is_some() {
                body.clone()
            } else {
                with_camera(&fence.lang, &body)
            };
            let path = scenes.path().join(&name);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &file).unwrap();
            // A part kept for later scenes is checked as the page says to check one.
            let part = kept.is_some() && !whole;
            let args: &[&str] = if part {
                &["check", "--part", &name]
            } else {
                &["check", &name]
            };
            let (ok, output) = tracer(scenes.path(), args);
            checked += 1;
            match &expected {
                Some((_, shown)) if !same_text(shown, &output) => problems.push(format!(
                    "{at}: `tracer check` prints\n{output}\nbut the page shows\n{shown}"
                )),
                None if !ok => problems.push(format!("{at}: `tracer check` fails:\n{output}")),
                _ => {}
            }
            if let Some(picture) = mark.as_deref().and_then(|m| m.strip_prefix("renders:")) {
                let picture = page.parent().unwrap().join(picture.trim());
                if let Some(problem) = renders_to(scenes.path(), &name, &picture) {
                    problems.push(format!("{at}: {problem}"));
                }
            }
            if kept.is_none() {
                std::fs::remove_file(&path).unwrap();
            }
        }
    }
    assert!(checked >= 40, "only {checked} blocks found");
    assert!(problems.is_empty(), "{}", problems.join("\n\n"));
}

/// The render of `name` matches `picture` as the goldens are matched: at
/// most 0.1 % of the pixels off by more than 2 levels in a channel.
fn renders_to(dir: &Path, name: &str, picture: &Path) -> Option<String> {
    let (ok, output) = tracer(dir, &["render", name, "-o", "picture.png", "-q"]);
    if !ok {
        return Some(format!("does not render: {output}"));
    }
    let made = image::open(dir.join("picture.png")).unwrap().to_rgb8();
    let shown = match image::open(picture) {
        Ok(image) => image.to_rgb8(),
        Err(e) => return Some(format!("{}: {e}", picture.display())),
    };
    if made.dimensions() != shown.dimensions() {
        return Some(format!(
            "{} is another size than the render",
            picture.display()
        ));
    }
    let off = made
        .pixels()
        .zip(shown.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 2))
        .count();
    let total = (made.width() * made.height()) as usize;
    (off * 1000 > total).then(|| {
        format!(
            "{} is not the block's render ({off} of {total} pixels differ): render it again with \
             tracer render -o",
            picture.display()
        )
    })
}

#[test]
fn every_explain_shown_is_what_tracer_explain_prints() {
    let mut shown = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        for fence in markdown::fences(&text) {
            let Some((command, expected)) = shown_output(&fence, "tracer explain ") else {
                continue;
            };
            let args: Vec<&str> = command.split_whitespace().skip(1).collect();
            let (ok, output) = tracer(&root(), &args);
            assert!(ok, "{}: {command}: {output}", page.display());
            assert!(
                same_text(&expected, &output),
                "{}:{}: `{command}` prints\n{output}",
                page.display(),
                fence.line
            );
            shown += 1;
        }
    }
    assert!(shown >= 2, "{shown} explained pixels shown");
}

/// The check itself: a scene that fails, shown as passing, is caught.
#[test]
fn a_mistake_shown_with_the_wrong_message_is_caught() {
    let dir = scenes_folder();
    std::fs::write(
        dir.path().join("typo.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfvo = 50\n",
    )
    .unwrap();
    let (ok, output) = tracer(dir.path(), &["check", "typo.toml"]);
    assert!(!ok);
    assert!(output.contains("did you mean `fov`"), "{output}");
    assert!(!same_text("  × unknown key `fov`", &output));
    // A part of a scene is whole with a camera; its mesh path is read as from scenes/.
    let part = "[[objects]]\nmesh = { obj = \"meshes/cube.obj\" }\n";
    assert!(!is_whole("toml", part));
    std::fs::write(dir.path().join("part.toml"), with_camera("toml", part)).unwrap();
    let (ok, output) = tracer(dir.path(), &["check", "part.toml"]);
    assert!(ok, "{output}");
}

/// `tracer --help` says where the book is: its pages in the repository, and
/// the built HTML when it has been built.
#[test]
fn the_help_points_to_the_book() {
    let (ok, help) = tracer(&root(), &["--help"]);
    assert!(ok, "{help}");
    assert!(help.contains("docs/src/SUMMARY.md"), "{help}");
    assert!(help.contains("cargo xtask book"), "{help}");
    assert!(root().join("docs/src/SUMMARY.md").is_file());
    let built = root().join("target/book/index.html");
    assert_eq!(help.contains("Built here: "), built.is_file(), "{help}");
}
