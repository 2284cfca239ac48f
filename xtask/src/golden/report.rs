//! The report for people: for every image its golden, its render and the heat
//! map of their difference, side by side in `index.html`, failures first. The
//! page links only files beside it, so it opens from disk with no server.

use super::check::{self, CaseResult, Outcome};
use super::compare::heat;
use anyhow::{Context, Result};
use image::RgbImage;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tracer_pipeline::output::{encode, ImageFormat};

/// The three pictures of one image, as files in the report folder.
pub fn golden_file(name: &str) -> String {
    format!("{name}-golden.png")
}
pub fn actual_file(name: &str) -> String {
    format!("{name}-actual.png")
}
pub fn diff_file(name: &str) -> String {
    format!("{name}-diff.png")
}

/// Writes the report folder `dir` whole: it is built beside `dir` and then
/// takes its place, so an old report is never mixed with a new one.
/// Returns the path of `index.html`.
pub fn write(dir: &Path, results: &[CaseResult]) -> Result<PathBuf> {
    let parent = dir
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent)
        .with_context(|| format!("cannot create {}", parent.display()))?;
    let staging = tempfile::Builder::new()
        .prefix(".golden-report-")
        .tempdir_in(parent)
        .with_context(|| format!("cannot create a folder in {}", parent.display()))?;
    for r in results {
        save(staging.path(), &golden_file(&r.name), r.golden.as_ref())?;
        save(staging.path(), &actual_file(&r.name), r.actual.as_ref())?;
        save(staging.path(), &diff_file(&r.name), r.diff.as_ref())?;
    }
    std::fs::write(staging.path().join("index.html"), html(results))
        .context("cannot write index.html")?;
    if dir.exists() {
        std::fs::remove_dir_all(dir)
            .with_context(|| format!("cannot replace {}", dir.display()))?;
    }
    std::fs::rename(staging.keep(), dir)
        .with_context(|| format!("cannot write {}", dir.display()))?;
    Ok(dir.join("index.html"))
}

fn save(dir: &Path, file: &str, image: Option<&RgbImage>) -> Result<()> {
    if let Some(image) = image {
        std::fs::write(dir.join(file), encode(image, ImageFormat::Png)?)
            .with_context(|| format!("cannot write {file}"))?;
    }
    Ok(())
}

/// How many `<img>` the page of these results holds.
pub fn image_count(results: &[CaseResult]) -> usize {
    results
        .iter()
        .map(|r| {
            [&r.golden, &r.actual, &r.diff]
                .iter()
                .filter(|i| i.is_some())
                .count()
        })
        .sum()
}

/// The page, in the terminal table's order and with its summary line.
pub fn html(results: &[CaseResult]) -> String {
    let order = check::report_order(results);
    let mut page = String::from(HEAD);
    let _ = write!(
        page,
        "<h1>Golden images: {}</h1>\n{}\n",
        check::summary_line(results),
        legend()
    );
    page.push_str(&summary_table(&order));
    for r in order {
        page.push_str(&section(r));
    }
    page.push_str(TAIL);
    page
}

fn legend() -> String {
    let swatch = |c: [u8; 3]| {
        format!(
            "<span class=\"swatch\" style=\"background:rgb({},{},{})\"></span>",
            c[0], c[1], c[2]
        )
    };
    format!(
        "<p class=\"legend\">Difference: identical pixels show the golden image dimmed; \
         {} differs within tolerance; {}&hellip;{} beyond it, from just over to 255 levels. \
         Numbers: pixels differing beyond tolerance, largest channel difference and mean \
         channel difference, in 8-bit levels. Click an image for full size.</p>\n\
         <output id=\"image-check\">Image check did not run (JavaScript off?).</output>",
        swatch(heat::WITHIN),
        swatch(heat::BEYOND_LOW),
        swatch(heat::BEYOND_HIGH)
    )
}

/// All the numbers at a glance, each name linking to its section.
fn summary_table(order: &[&CaseResult]) -> String {
    let mut s = String::from(
        "<table>\n<tr><th>image</th><th>pixels differing</th><th>max diff</th>\
         <th>mean diff</th><th>result</th></tr>\n",
    );
    for r in order {
        let numbers = match &r.outcome {
            Outcome::Compared(c) => format!(
                "<td>{} ({:.3} %)</td><td>{}</td><td>{:.4}</td>",
                c.differing,
                c.differing_percent(),
                c.max_diff,
                c.mean_diff
            ),
            _ => "<td>-</td><td>-</td><td>-</td>".to_string(),
        };
        let _ = writeln!(
            s,
            "<tr class=\"{}\"><td><a href=\"#case-{}\">{}</a></td>{numbers}<td>{}</td></tr>",
            r.verdict().to_ascii_lowercase(),
            url_escape(&r.name),
            escape(&r.name),
            r.verdict()
        );
    }
    s.push_str("</table>\n");
    s
}

fn section(r: &CaseResult) -> String {
    let name = escape(&r.name);
    let verdict = r.verdict();
    let mut s = format!(
        "<section id=\"case-{}\" class=\"{}\">\n<h2>{name} <span class=\"verdict\">{verdict}</span></h2>\n",
        url_escape(&r.name),
        verdict.to_ascii_lowercase()
    );
    s.push_str(&numbers(r));
    if let Some(problem) = r.problem() {
        let _ = writeln!(s, "<p class=\"problem\">{}</p>", escape(&problem));
    }
    s.push_str("<div class=\"row\">\n");
    s.push_str(&figure("golden", &golden_file(&r.name), r.golden.is_some()));
    s.push_str(&figure("actual", &actual_file(&r.name), r.actual.is_some()));
    s.push_str(&figure("difference", &diff_file(&r.name), r.diff.is_some()));
    s.push_str("</div>\n</section>\n");
    s
}

fn numbers(r: &CaseResult) -> String {
    let t = &r.tolerance;
    let tolerance = format!(
        "tolerance: channel &gt; {}/255, at most {} % of pixels",
        t.channel, t.max_differing_percent
    );
    match &r.outcome {
        Outcome::Compared(c) => format!(
            "<p class=\"numbers\">{} of {} pixels differ ({:.3} %) &middot; max diff {} \
             &middot; mean diff {:.4} &middot; {tolerance}</p>\n",
            c.differing,
            c.pixels,
            c.differing_percent(),
            c.max_diff,
            c.mean_diff
        ),
        _ => format!("<p class=\"numbers\">{tolerance}</p>\n"),
    }
}

fn figure(label: &str, file: &str, present: bool) -> String {
    let content = if present {
        let src = url_escape(file);
        format!(
            "<a href=\"{src}\"><img src=\"{src}\" alt=\"{} ({label})\"></a>",
            escape(file)
        )
    } else {
        "<div class=\"none\">none</div>".to_string()
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
<title>Golden images</title>
<style>
body { font-family: sans-serif; margin: 1em 2em; background: #f4f4f4; color: #222; }
section { background: #fff; margin: 1em 0; padding: 0.5em 1em; border-left: 8px solid #2a2; }
section.fail, section.missing, section.error { border-left-color: #d22; }
h2 { margin: 0.3em 0; font-size: 1.2em; }
.verdict { font-size: 0.8em; padding: 0 0.4em; color: #fff; background: #2a2; }
.fail .verdict, .missing .verdict, .error .verdict { background: #d22; }
.problem { color: #b00; font-weight: bold; }
.numbers { font-family: monospace; }
.row { display: flex; gap: 1em; flex-wrap: wrap; }
figure { margin: 0; flex: 1 1 0; min-width: 200px; }
figure img { width: 100%; image-rendering: pixelated; display: block; }
.none { padding: 3em 0; text-align: center; background: #ddd; color: #666; }
.swatch { display: inline-block; width: 1em; height: 1em; vertical-align: middle; }
table { border-collapse: collapse; background: #fff; font-family: monospace; }
td, th { padding: 0.1em 0.8em; text-align: right; }
td:first-child, th:first-child { text-align: left; }
tr.fail td, tr.missing td, tr.error td { color: #b00; font-weight: bold; }
#image-check { display: block; margin: 0.5em 0; }
#image-check.bad { color: #b00; font-weight: bold; }
</style>
</head>
<body>
"#;

/// Records in the page whether every image loaded, for people and for the
/// browser test, which reads the `data-*` attributes from the dumped DOM.
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
            url_escape("my scene#1-golden.png"),
            "my%20scene%231-golden.png"
        );
    }
}
