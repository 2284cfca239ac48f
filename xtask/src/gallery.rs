//! `cargo xtask gallery`: `docs/gallery.md`, every scene of `scenes/` (its
//! folders too) and the lab's other images, each as its golden with the
//! command that makes it. Made from the same list of images as
//! `cargo xtask golden`, so a new scene shows up in both; a test keeps the
//! committed file current.

use crate::golden::{lab_image_cases, scene_files};
use anyhow::{bail, Context, Result};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Where the gallery is, relative to the workspace root.
pub const GALLERY: &str = "docs/gallery.md";

/// The lab's images that are not scene renders, as `tracer` makes them
/// (the golden tool's `lab_image_cases`): name, command, what it shows.
const LAB_IMAGES: [(&str, &str, &str); 6] = [
    (
        "gradient-OX",
        "tracer render scenes/sphere-intersection.toml --aov ray-dir-x -o gradient-OX.png",
        "Lab exercise 6: the x of each primary ray's direction d, as (d + 1) / 2 in red.",
    ),
    (
        "gradient-OY",
        "tracer render scenes/sphere-intersection.toml --aov ray-dir-y -o gradient-OY.png",
        "Lab exercise 6: the y of each primary ray's direction, in green.",
    ),
    (
        "gradient-OZ",
        "tracer render scenes/sphere-intersection.toml --aov ray-dir-z -o gradient-OZ.png",
        "Lab exercise 6: the z of each primary ray's direction, in blue.",
    ),
    (
        "calib-chart",
        "tracer calib-chart -o calib-chart.png",
        "Lab exercise 17: the calibration chart, five patches 0, 0.25, 0.5, 0.75 and 1, \
         no gamma encoding.",
    ),
    (
        "calib-chart-gamma-2.2",
        "tracer calib-chart --gamma 2.2 -o calib-chart-gamma-2.2.png",
        "The same chart encoded for a display of gamma 2.2.",
    ),
    (
        "gamma-plot",
        "tracer gamma fit scenes/gamma/sample-measurements.csv --plot gamma-plot.png",
        "A display's gamma fitted to the sample measurements: the measured points, the \
         fitted and the correcting curves, the corrected points.",
    ),
];

/// One picture of the gallery.
struct Entry {
    /// The golden's name: `golden/<name>.png`.
    name: String,
    heading: String,
    caption: String,
    command: String,
}

/// The gallery's Markdown for the workspace at `root`.
pub fn render(root: &Path) -> Result<String> {
    let scenes = scene_entries(root)?;
    let lab = lab_entries(root)?;
    let mut out = String::from(
        "# Gallery\n\n\
         Every scene in `scenes/` (its folders too) and the lab's other images, as their \
         reference images in `golden/` show them, each with the command that makes it \
         (run from the top of the repository; `cargo run --release --bin tracer --` in \
         place of `tracer` without an installed one). Written by `cargo xtask gallery` \
         from the scene files and the goldens; a test checks it is current.\n",
    );
    section(&mut out, root, "Scenes", &scenes);
    section(&mut out, root, "The lab's other images", &lab);
    Ok(out)
}

/// Writes the gallery to `root/docs/gallery.md`; returns its path.
pub fn write(root: &Path) -> Result<PathBuf> {
    let path = root.join(GALLERY);
    let text = render(root)?;
    std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(path)
}

fn scene_entries(root: &Path) -> Result<Vec<Entry>> {
    scene_files(&root.join("scenes"))?
        .into_iter()
        .map(|(name, path)| {
            let file = relative(root, &path)?;
            let text = std::fs::read_to_string(&path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            Ok(Entry {
                command: format!("tracer render {file} -o {name}.png"),
                heading: format!("`{file}`"),
                caption: caption(&text),
                name,
            })
        })
        .collect()
}

/// The lab images in the golden tool's order; one it makes that has no
/// command here is an error, so the two lists cannot part.
fn lab_entries(root: &Path) -> Result<Vec<Entry>> {
    lab_image_cases(root)
        .into_iter()
        .map(|case| {
            let Some((_, command, caption)) = LAB_IMAGES.iter().find(|(n, ..)| *n == case.name)
            else {
                bail!("the gallery has no command for the lab image {}", case.name);
            };
            Ok(Entry {
                heading: case.name.clone(),
                caption: caption.to_string(),
                command: command.to_string(),
                name: case.name,
            })
        })
        .collect()
}

fn section(out: &mut String, root: &Path, title: &str, entries: &[Entry]) {
    let _ = write!(out, "\n## {title}\n");
    for entry in entries {
        let _ = write!(out, "\n### {}\n\n", entry.heading);
        if !entry.caption.is_empty() {
            let _ = write!(out, "{}\n\n", entry.caption);
        }
        let _ = write!(out, "    {}\n\n", entry.command);
        let golden = format!("golden/{}.png", entry.name);
        if root.join(&golden).is_file() {
            let _ = writeln!(out, "![{}](../{golden})", entry.name);
        } else {
            let _ = writeln!(
                out,
                "No golden yet: look at the render, then `cargo xtask golden --bless {}`.",
                entry.name
            );
        }
    }
}

/// `path` relative to `root`, with `/` between its parts (as in the README).
fn relative(root: &Path, path: &Path) -> Result<String> {
    let rel = path
        .strip_prefix(root)
        .with_context(|| format!("{} is outside {}", path.display(), root.display()))?;
    let parts: Option<Vec<&str>> = rel.iter().map(|p| p.to_str()).collect();
    parts
        .map(|p| p.join("/"))
        .with_context(|| format!("{}: the path is not UTF-8", rel.display()))
}

/// A scene file's first comment paragraph (its leading `#` lines up to an
/// empty one), as one line: what the scene shows. A `#:schema` directive
/// is not part of it.
pub fn caption(text: &str) -> String {
    text.lines()
        .filter(|line| !line.starts_with("#:schema"))
        .map_while(|line| line.strip_prefix('#'))
        .map(str::trim)
        .take_while(|line| !line.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}
