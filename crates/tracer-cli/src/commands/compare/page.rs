//! The report of `tracer compare --report`: a folder holding `index.html`
//! (every image beside its reference and heat-map, with its numbers, worst
//! first; the page links only files beside it, so it opens from disk),
//! `report.csv` (one row per image, in the same order), the images, and
//! `.tracer-report`, the list of the files it wrote. The folder is made
//! beside its place and filled as each image is compared (so memory does
//! not grow with the class), then takes its place whole. A folder already
//! there is replaced only if it holds nothing but the files its own list
//! names: an earlier report, never a user's files.

use super::comparison::Comparison;
use super::input::{BadInput, Reference};
use super::pair::{percent, rgb};
use anyhow::{Context, Result};
use image::RgbImage;
use scene_format::visible::escape_controls;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tracer_pipeline::output::{encode, ImageFormat, PendingFolder};

/// One image of the class, compared; its files are in the report folder.
pub struct Entry {
    pub path: PathBuf,
    pub scene: String,
    /// Its place among the class's images (their path order): its files'
    /// names until it is ranked.
    pub index: usize,
    /// The comparison, its heat-map already written (and let go).
    pub comparison: Comparison,
    pub heat_map: bool,
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

/// An image named after no scene.
pub struct Unmatched {
    pub path: PathBuf,
    /// Its name (or its folder's) is not UTF-8: it cannot be matched.
    pub name_not_text: bool,
}

impl Unmatched {
    /// Why it was skipped, after its path.
    pub fn why(&self) -> &'static str {
        if self.name_not_text {
            "its name cannot be read as text (it is not UTF-8), so no scene's name can match it; rename it"
        } else {
            "is named after no scene"
        }
    }
}

/// What the report shows: the images compared, worst first, those that
/// could not be read and those named after no scene.
pub struct Class {
    pub entries: Vec<Entry>,
    pub unreadable: Vec<Unreadable>,
    pub unmatched: Vec<Unmatched>,
}

/// The list of the files a report wrote, in the report: what shows that
/// a folder is a report, which may be replaced.
const LIST: &str = ".tracer-report";
/// The list's first line.
const LIST_HEADER: &str =
    "# The files `tracer compare --report` wrote here; the next report replaces them.";

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
    if std::fs::symlink_metadata(out).is_ok() && !is_empty_folder(out) {
        if let Err(why) = report_files(out) {
            return Err(BadInput(format!(
                "{}: exists and {why}; refusing to replace it (choose another -o, or empty it)",
                out.display()
            ))
            .into());
        }
    }
    Ok(())
}

/// Whether `dir` is a folder that holds nothing: nothing to lose.
fn is_empty_folder(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut entries| entries.next().is_none())
}

/// Whether `dir` is a report `tracer compare --report` wrote and nothing
/// else.
pub fn is_report(dir: &Path) -> bool {
    report_files(dir).is_ok()
}

/// Why `dir` is not a report and nothing else, if it is not: not a folder,
/// without the list of the files a report wrote, or holding another file.
fn report_files(dir: &Path) -> Result<(), String> {
    if !std::fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
        return Err("is not a folder".to_string());
    }
    let not_listed = || {
        format!("is not a report of `tracer compare --report` (it has no {LIST}, the list of the files a report wrote)")
    };
    let list = std::fs::read_to_string(dir.join(LIST)).map_err(|_| not_listed())?;
    let mut lines = list.lines();
    if lines.next() != Some(LIST_HEADER) {
        return Err(not_listed());
    }
    let written: Vec<&str> = lines.collect();
    let entries = std::fs::read_dir(dir).map_err(|e| format!("cannot be read ({e})"))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("cannot be read ({e})"))?;
        let name = entry.file_name();
        let ours = name
            .to_str()
            .is_some_and(|n| n == LIST || written.contains(&n));
        let file = entry.file_type().is_ok_and(|t| t.is_file());
        if !ours || !file {
            let name = escape_controls(&name.to_string_lossy());
            return Err(format!(
                "holds {name}, which is not a file of the report written there"
            ));
        }
    }
    Ok(())
}

fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// The report being written: its folder beside `out`, filled as the
/// images are compared.
pub struct Report {
    folder: PendingFolder,
}

impl Report {
    /// Makes the report's folder beside `out` (checked by `check_out`).
    pub fn begin(out: &Path) -> Result<Report> {
        let parent = parent_of(out);
        let folder = PendingFolder::create(parent, ".tracer-report-")
            .with_context(|| format!("cannot create a folder in {}", parent.display()))?;
        Ok(Report { folder })
    }

    fn write(&self, name: &str, bytes: &[u8]) -> Result<()> {
        std::fs::write(self.folder.path().join(name), bytes)
            .with_context(|| format!("cannot write {name} of the report"))
    }

    /// A scene's reference image.
    pub fn reference(&self, scene: &str, reference: &Reference) -> Result<()> {
        self.write(&reference_file(scene), &png(&reference.image)?)
    }

    /// Image `index` of the class and its heat-map, named by `index` until
    /// ranked: written now, so nothing of them stays in memory.
    pub fn image(&self, index: usize, image: &RgbImage, heat_map: Option<&RgbImage>) -> Result<()> {
        self.write(&unranked(index, "image"), &png(image)?)?;
        if let Some(map) = heat_map {
            self.write(&unranked(index, "heatmap"), &png(map)?)?;
        }
        Ok(())
    }

    /// The images' files named by their rank, the page, the CSV and the
    /// list written; then the folder takes the place of `out`.
    pub fn finish(
        self,
        out: &Path,
        class: &Class,
        references: &BTreeMap<String, Reference>,
        tolerance: u8,
    ) -> Result<()> {
        let entries = &class.entries;
        let mut names = vec!["index.html".to_string(), "report.csv".to_string()];
        names.extend(references.keys().map(|scene| reference_file(scene)));
        let dir = self.folder.path();
        for (rank, e) in entries.iter().enumerate() {
            let mut files = vec![(unranked(e.index, "image"), image_file(rank, entries.len()))];
            if e.heat_map {
                files.push((
                    unranked(e.index, "heatmap"),
                    heat_map_file(rank, entries.len()),
                ));
            }
            for (from, to) in files {
                std::fs::rename(dir.join(&from), dir.join(&to))
                    .with_context(|| format!("cannot name {to} of the report"))?;
                names.push(to);
            }
        }
        self.write("index.html", html(class, tolerance).as_bytes())?;
        self.write("report.csv", &csv(class)?)?;
        self.write(
            LIST,
            (LIST_HEADER.to_string() + "\n" + &names.join("\n") + "\n").as_bytes(),
        )?;
        replace_folder(out, self.folder)
    }
}

/// Image `index`'s file before it is ranked.
fn unranked(index: usize, what: &str) -> String {
    format!("unranked-{index}-{what}.png")
}

fn png(image: &RgbImage) -> Result<Vec<u8>> {
    Ok(encode(image, ImageFormat::Png)?)
}

/// Puts `staging` in the place of `out`: an earlier report there (checked
/// again: a file added to it since the start is not lost) is moved aside
/// and deleted once the new one is in place.
fn replace_folder(out: &Path, staging: PendingFolder) -> Result<()> {
    check_out(out)?;
    let parent = parent_of(out);
    let old = tempfile::Builder::new()
        .prefix(".tracer-old-report-")
        .tempdir_in(parent)
        .with_context(|| format!("cannot create a folder in {}", parent.display()))?;
    let aside = old.path().join("report");
    if std::fs::symlink_metadata(out).is_ok() {
        std::fs::rename(out, &aside)
            .with_context(|| format!("cannot replace {}", out.display()))?;
    }
    if let Err(e) = staging.rename_to(out) {
        let _ = std::fs::rename(&aside, out);
        return Err(e).with_context(|| format!("cannot write {}", out.display()));
    }
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
        for u in &class.unmatched {
            let why = if u.name_not_text {
                format!(": {}", u.why())
            } else {
                String::new()
            };
            let _ = writeln!(
                page,
                "<li>{}{}</li>",
                escape(&u.path.display().to_string()),
                escape(&why)
            );
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
    let heat_map = e.heat_map.then(|| heat_map_file(rank, count));
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

/// Text for the page: control and bidirectional characters made visible
/// (a name holding U+202E would show reversed, as another student's),
/// then HTML's own characters escaped.
fn escape(text: &str) -> String {
    escape_controls(text)
        .replace('&', "&amp;")
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
            escape("alice\u{202e}gnp.bob\u{1b}[2J"),
            "alice\\u{202e}gnp.bob\\u{1b}[2J"
        );
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
