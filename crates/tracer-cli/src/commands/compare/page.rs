//! The report of `tracer compare --report`: a folder holding `index.html`
//! (every image beside its reference and heat-map, with its numbers, worst
//! first; the page links only files beside it, so it opens from disk),
//! `report.csv` (one row per image, in the same order) and the images.

use super::comparison::Comparison;
use super::input::{BadInput, Reference};
use super::pair::{percent, rgb};
use anyhow::{Context, Result};
use image::RgbImage;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tracer_pipeline::output::{encode, ImageFormat};

/// One image of the class, compared.
pub struct Entry {
    pub path: PathBuf,
    pub scene: String,
    pub image: RgbImage,
    pub comparison: Comparison,
}

/// An image of the class that could not be read, and why.
pub struct Unreadable {
    pub path: PathBuf,
    pub scene: String,
    pub why: String,
    /// The image read, its scene not: `not compared:` in the CSV, where
    /// an image that cannot be read is `unreadable:`.
    pub scene_failed: bool,
}

/// What the report shows: the images compared, worst first, those that
/// could not be read and those named after no scene.
pub struct Class {
    pub entries: Vec<Entry>,
    pub unreadable: Vec<Unreadable>,
    pub unmatched: Vec<PathBuf>,
}

/// The files that show that `out` is a report, which may be replaced.
const REPORT_FILES: [&str; 2] = ["index.html", "report.csv"];

/// Refuses, before the work, an `out` that could not take the report: in
/// a folder that does not exist, or something else than an earlier report
/// (which would be lost).
pub fn check_out(out: &Path) -> Result<()> {
    let parent = parent_of(out);
    if !parent.is_dir() {
        anyhow::bail!(
            "{}: the folder {} does not exist",
            out.display(),
            parent.display()
        );
    }
    if out.exists() && !is_report(out) {
        return Err(BadInput(format!(
            "{}: exists and is not a report of `tracer compare --report`; refusing to replace it",
            out.display()
        ))
        .into());
    }
    Ok(())
}

/// Whether `dir` is a report `tracer compare --report` wrote.
pub fn is_report(dir: &Path) -> bool {
    dir.is_dir() && REPORT_FILES.iter().all(|f| dir.join(f).is_file())
}

fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Writes the report folder `out` whole: it is made beside `out` and then
/// takes its place, so an old report is never mixed with a new one.
pub fn write(
    out: &Path,
    class: &Class,
    references: &BTreeMap<String, Reference>,
    tolerance: u8,
) -> Result<()> {
    let entries = &class.entries;
    // Everything is encoded before the folder is made: it lives for the
    // few writes only (a signal then would leave it behind).
    let mut files = vec![
        (
            "index.html".to_string(),
            html(class, tolerance).into_bytes(),
        ),
        ("report.csv".to_string(), csv(class)?),
    ];
    for (scene, reference) in references {
        files.push((reference_file(scene), png(&reference.image)?));
    }
    for (rank, e) in entries.iter().enumerate() {
        files.push((image_file(rank, entries.len()), png(&e.image)?));
        if let Some(map) = e.comparison.heat_map() {
            files.push((heat_map_file(rank, entries.len()), png(map)?));
        }
    }
    replace_folder(out, &files)
}

fn png(image: &RgbImage) -> Result<Vec<u8>> {
    Ok(encode(image, ImageFormat::Png)?)
}

fn replace_folder(out: &Path, files: &[(String, Vec<u8>)]) -> Result<()> {
    let parent = parent_of(out);
    let staging = tempfile::Builder::new()
        .prefix(".tracer-report-")
        .tempdir_in(parent)
        .with_context(|| format!("cannot create a folder in {}", parent.display()))?;
    for (name, bytes) in files {
        std::fs::write(staging.path().join(name), bytes)
            .with_context(|| format!("cannot write {name} of the report"))?;
    }
    // The old report is moved aside, not deleted, until the new one is in place.
    let old = tempfile::Builder::new()
        .prefix(".tracer-old-report-")
        .tempdir_in(parent)
        .with_context(|| format!("cannot create a folder in {}", parent.display()))?;
    let aside = old.path().join("report");
    if out.exists() {
        std::fs::rename(out, &aside)
            .with_context(|| format!("cannot replace {}", out.display()))?;
    }
    if let Err(e) = std::fs::rename(staging.path(), out) {
        let _ = std::fs::rename(&aside, out);
        return Err(e).with_context(|| format!("cannot write {}", out.display()));
    }
    // Now in place: `staging` must not remove it.
    let _ = staging.keep();
    Ok(())
}

fn reference_file(scene: &str) -> String {
    format!("reference-{scene}.png")
}

/// An image's files are named by its rank, so two students' images of one
/// scene never clash.
fn image_file(rank: usize, count: usize) -> String {
    format!("{}-image.png", rank_text(rank, count))
}

fn heat_map_file(rank: usize, count: usize) -> String {
    format!("{}-heatmap.png", rank_text(rank, count))
}

fn rank_text(rank: usize, count: usize) -> String {
    let digits = count.to_string().len();
    format!("{:0digits$}", rank + 1)
}

/// `report.csv`: a header, then one row per image, worst first, then
/// the unreadable ones (their numbers empty, `unreadable: why` their
/// mistakes).
fn csv(class: &Class) -> Result<Vec<u8>> {
    let mut writer = csv::Writer::from_writer(Vec::new());
    writer.write_record([
        "image",
        "scene",
        "differing",
        "largest",
        "x",
        "y",
        "psnr_db",
        "flip",
        "mistakes",
    ])?;
    for e in &class.entries {
        writer.write_record(csv_row(e))?;
    }
    for u in &class.unreadable {
        let mut row = vec![u.path.display().to_string(), u.scene.clone()];
        row.extend(vec![String::new(); 6]);
        let label = if u.scene_failed {
            "not compared"
        } else {
            "unreadable"
        };
        row.push(format!("{label}: {}", u.why));
        writer.write_record(row)?;
    }
    Ok(writer.into_inner().map_err(|e| e.into_error())?)
}

/// One row: `differing` is the share of pixels off, 0 to 1 (1 for
/// images of another size); the largest channel difference and its pixel;
/// PSNR (`inf` when identical); FLIP's mean; the mistakes' words.
fn csv_row(e: &Entry) -> Vec<String> {
    let mut row = vec![
        e.path.display().to_string(),
        e.scene.clone(),
        format!("{:.6}", e.comparison.share()),
    ];
    match &e.comparison {
        Comparison::Sizes { .. } => row.extend(vec![String::new(); 5]),
        Comparison::Compared {
            difference, flip, ..
        } => {
            let (largest, x, y) = match difference.largest {
                Some(p) => (p.difference().to_string(), p.x.to_string(), p.y.to_string()),
                None => ("0".to_string(), String::new(), String::new()),
            };
            let psnr = difference
                .psnr()
                .map_or("inf".to_string(), |p| format!("{p:.2}"));
            let flip = flip
                .as_ref()
                .map_or(String::new(), |f| format!("{:.4}", f.mean));
            row.extend([largest, x, y, psnr, flip]);
        }
    }
    row.push(e.comparison.words().join("; "));
    row
}

/// `index.html`.
fn html(class: &Class, tolerance: u8) -> String {
    let entries = &class.entries;
    let within = entries
        .iter()
        .filter(|e| e.comparison.within_tolerance())
        .count();
    let unreadable = match class.unreadable.len() {
        0 => String::new(),
        n => format!("; {n} not compared"),
    };
    let mut page = String::from(HEAD);
    let _ = write!(
        page,
        "<h1>{} images compared: {within} within tolerance, {} not{unreadable}</h1>\n\
         <p class=\"legend\">Worst first. A pixel is off when a channel differs by more than \
         {tolerance} of 255. The heat-map is FLIP's error (Andersson et al. 2020) in its magma \
         colours: black where no difference shows, through purple and orange to yellow for \
         the largest. Click an image for full size.</p>\n\
         <output id=\"image-check\">Image check did not run (JavaScript off?).</output>\n",
        entries.len(),
        entries.len() - within
    );
    page += &summary_table(entries);
    for (rank, e) in entries.iter().enumerate() {
        page += &section(rank, entries.len(), e);
    }
    if !class.unreadable.is_empty() {
        page += "<h2 class=\"fail\">Not compared</h2>\n<ul>\n";
        for u in &class.unreadable {
            let _ = writeln!(
                page,
                "<li>{} <span class=\"scene\">({})</span>: {}</li>",
                escape(&u.path.display().to_string()),
                escape(&u.scene),
                escape(&u.why)
            );
        }
        page += "</ul>\n";
    }
    if !class.unmatched.is_empty() {
        page += "<h2>Not compared: named after no scene</h2>\n<ul>\n";
        for path in &class.unmatched {
            let _ = writeln!(page, "<li>{}</li>", escape(&path.display().to_string()));
        }
        page += "</ul>\n";
    }
    page += TAIL;
    page
}

fn summary_table(entries: &[Entry]) -> String {
    let mut s = String::from(
        "<table>\n<tr><th>image</th><th>scene</th><th>off</th><th>FLIP</th><th>mistakes</th></tr>\n",
    );
    for (rank, e) in entries.iter().enumerate() {
        let flip = e
            .comparison
            .flip_mean()
            .map_or("-".to_string(), |f| format!("{f:.4}"));
        let _ = writeln!(
            s,
            "<tr class=\"{}\"><td><a href=\"#image-{}\">{}</a></td><td>{}</td><td>{}</td>\
             <td>{flip}</td><td>{}</td></tr>",
            class(&e.comparison),
            rank + 1,
            escape(&e.path.display().to_string()),
            escape(&e.scene),
            percent(e.comparison.share()),
            escape(&e.comparison.words().join(", "))
        );
    }
    s + "</table>\n"
}

fn class(comparison: &Comparison) -> &'static str {
    if comparison.within_tolerance() {
        "pass"
    } else {
        "fail"
    }
}

fn section(rank: usize, count: usize, e: &Entry) -> String {
    let mut s = format!(
        "<section id=\"image-{}\" class=\"{}\">\n<h2>{}. {} <span class=\"scene\">({})</span></h2>\n",
        rank + 1,
        class(&e.comparison),
        rank + 1,
        escape(&e.path.display().to_string()),
        escape(&e.scene)
    );
    s += &numbers(&e.comparison);
    for line in e.comparison.diagnoses() {
        let _ = writeln!(s, "<p class=\"mistake\">{}</p>", escape(&line));
    }
    s += "<div class=\"row\">\n";
    s += &figure("image", Some(&image_file(rank, count)));
    s += &figure("reference", Some(&reference_file(&e.scene)));
    let heat_map = e.comparison.heat_map().map(|_| heat_map_file(rank, count));
    s += &figure("heat-map", heat_map.as_deref());
    s + "</div>\n</section>\n"
}

fn numbers(comparison: &Comparison) -> String {
    let Comparison::Compared {
        difference, flip, ..
    } = comparison
    else {
        return String::new();
    };
    let largest = match difference.largest {
        Some(p) => format!(
            "largest {} at ({}, {}): image {}, reference {}",
            p.difference(),
            p.x,
            p.y,
            rgb(p.image),
            rgb(p.reference)
        ),
        None => "identical".to_string(),
    };
    let psnr = difference
        .psnr()
        .map_or("infinite".to_string(), |p| format!("{p:.2} dB"));
    let flip = flip
        .as_ref()
        .map_or("not computed (too large)".to_string(), |f| {
            format!("{:.4}", f.mean)
        });
    format!(
        "<p class=\"numbers\">{} off ({} of {} pixels) &middot; {largest} &middot; \
         PSNR {psnr} &middot; FLIP {flip}</p>\n",
        percent(difference.share()),
        difference.differing,
        difference.pixels,
    )
}

fn figure(label: &str, file: Option<&str>) -> String {
    let content = match file {
        Some(file) => {
            let src = url_escape(file);
            format!("<a href=\"{src}\"><img src=\"{src}\" alt=\"{label}\"></a>")
        }
        None => "<div class=\"none\">none: the sizes differ</div>".to_string(),
    };
    format!("<figure><figcaption>{label}</figcaption>{content}</figure>\n")
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A file name as a relative URL: every byte outside the unreserved set escaped.
fn url_escape(file: &str) -> String {
    file.bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect()
}

const HEAD: &str = r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>tracer compare: report</title>
<style>
body { font-family: sans-serif; margin: 1em 2em; background: #f4f4f4; color: #222; }
section { background: #fff; margin: 1em 0; padding: 0.5em 1em; border-left: 8px solid #2a2; }
section.fail { border-left-color: #d22; }
h2 { margin: 0.3em 0; font-size: 1.2em; }
.scene { font-weight: normal; color: #666; }
.mistake { color: #b00; font-weight: bold; }
.numbers { font-family: monospace; }
.row { display: flex; gap: 1em; flex-wrap: wrap; }
figure { margin: 0; flex: 1 1 0; min-width: 200px; }
figure img { width: 100%; image-rendering: pixelated; display: block; }
.none { padding: 3em 0; text-align: center; background: #ddd; color: #666; }
table { border-collapse: collapse; background: #fff; font-family: monospace; }
td, th { padding: 0.1em 0.8em; text-align: left; }
tr.fail td { color: #b00; }
h2.fail { color: #b00; }
#image-check { display: block; margin: 0.5em 0; }
#image-check.bad { color: #b00; font-weight: bold; }
</style>
</head>
<body>
"#;

/// Records in the page whether every image loaded, for people and for the
/// browser test, which reads the `data-*` attributes from the dumped DOM
/// (as the golden report does).
const TAIL: &str = r#"<script>
window.addEventListener("load", function () {
  var images = Array.prototype.slice.call(document.images);
  var failed = images.filter(function (img) { return !(img.complete && img.naturalWidth > 0); });
  var names = failed.map(function (img) { return img.getAttribute("src"); });
  var out = document.getElementById("image-check");
  out.setAttribute("data-total", String(images.length));
  out.setAttribute("data-loaded", String(images.length - failed.length));
  out.setAttribute("data-failed", names.join(" "));
  out.textContent = failed.length === 0
    ? "All " + images.length + " images loaded."
    : failed.length + " of " + images.length + " images did not load: " + names.join(", ");
  if (failed.length > 0) { out.className = "bad"; }
});
</script>
</body>
</html>
"#;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_escaped_for_html_and_urls() {
        assert_eq!(escape("a<b>&\"c"), "a&lt;b&gt;&amp;&quot;c");
        assert_eq!(
            url_escape("reference-my scene#1.png"),
            "reference-my%20scene%231.png"
        );
    }

    #[test]
    fn ranks_are_padded_to_sort_as_text() {
        assert_eq!(image_file(0, 12), "01-image.png");
        assert_eq!(heat_map_file(11, 12), "12-heatmap.png");
        assert_eq!(image_file(0, 5), "1-image.png");
    }
}
