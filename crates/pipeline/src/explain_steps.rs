//! An explained pixel's text as steps, for the playground's folding tree,
//! its `Next` and `Back` and its links between lines and drawn rays: each
//! line of the one formatter's text (`explain_text`), with its depth, the
//! lab's section it is about, the step it belongs to, and the ray of the
//! `Drawing` it tells of. Read back from the text rather than written
//! beside it, so that the page shows exactly what `tracer explain` prints.

use crate::explain::ExplainedPixel;
use crate::explain::Trace;
use crate::explain_draw::{Drawing, DrawnKind};
use serde::Serialize;

/// One line of the explanation.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Line {
    /// As written, without its indentation.
    pub text: String,
    /// Its indentation, in steps of two spaces: the tree's depth.
    pub depth: usize,
    /// The step (of the lab's algorithm) it belongs to, 0 the first: a
    /// formula written over several lines is one step.
    pub step: usize,
    /// The lab's section it is about: "1.2.3" the primary ray, "1.3" the
    /// intersections, "1.4" the lights' terms and shadow rays, "1.5" the
    /// mirror and glass rays, "gamma" the pixel's encoding, "path" a
    /// path's event.
    pub section: Option<&'static str>,
    /// The ray of the drawing (its `id`) it tells of.
    pub ray: Option<usize>,
}

/// `text`, the explanation of `pixel` as `explain_text` writes it, as lines.
pub fn lines(text: &str, pixel: &ExplainedPixel) -> Vec<Line> {
    let path = matches!(pixel.explanation.trace, Trace::Path { .. });
    let mut reader = Reader {
        drawing: &pixel.drawing,
        tree_rays: pixel
            .drawing
            .rays
            .iter()
            .filter(|r| {
                matches!(
                    r.kind,
                    DrawnKind::Primary | DrawnKind::Reflected | DrawnKind::Refracted
                )
            })
            .map(|r| r.id)
            .collect::<Vec<_>>()
            .into_iter(),
        open: Vec::new(),
        light: None,
        path_event: None,
        path,
    };
    let mut out: Vec<Line> = Vec::new();
    for raw in text.lines() {
        let trimmed = raw.trim_start_matches(' ');
        let spaces = raw.len() - trimmed.len();
        let (section, ray) = reader.read(trimmed, spaces);
        // A formula cut over lines ends each but its last in a comma.
        let continued = out.last().is_some_and(|l| l.text.ends_with(','));
        let step = match out.last() {
            Some(last) if continued => last.step,
            Some(last) => last.step + 1,
            None => 0,
        };
        let (section, ray) = match out.last() {
            Some(last) if continued => (last.section, last.ray),
            _ => (section, ray),
        };
        out.push(Line {
            text: trimmed.to_string(),
            depth: spaces / 2,
            step,
            section,
            ray,
        });
    }
    out
}

/// Where the reading is in the tree.
struct Reader<'a> {
    drawing: &'a Drawing,
    /// The primary, mirror and refracted rays, in the order the text
    /// tells them (depth first, as drawn).
    tree_rays: std::vec::IntoIter<usize>,
    /// The rays whose lines are being read, with their lines' indentation.
    open: Vec<(usize, usize)>,
    /// The light whose terms are being read (its index, the indentation
    /// of its `lights[K]` line).
    light: Option<(usize, usize)>,
    /// In path mode, once the path's events begin: the next event's index.
    path_event: Option<usize>,
    path: bool,
}

impl Reader<'_> {
    /// The section and ray of the line `trimmed`, indented `spaces`.
    fn read(&mut self, trimmed: &str, spaces: usize) -> (Option<&'static str>, Option<usize>) {
        if let Some(k) = self.path_event {
            return self.path_line(trimmed, k);
        }
        if self.path && trimmed.starts_with("the path (") {
            self.path_event = Some(0);
            self.open.clear();
            return (Some("path"), None);
        }
        while self
            .open
            .last()
            .is_some_and(|&(indent, _)| indent >= spaces)
        {
            self.open.pop();
        }
        if self.light.is_some_and(|(_, indent)| indent >= spaces) {
            self.light = None;
        }
        let ray_kind = [
            "primary ray from ",
            "mirror ray from ",
            "refracted ray from ",
        ]
        .iter()
        .position(|k| trimmed.starts_with(k));
        if let Some(kind) = ray_kind {
            let id = self.tree_rays.next();
            if let Some(id) = id {
                self.open.push((spaces, id));
            }
            return (Some(if kind == 0 { "1.2.3" } else { "1.5" }), id);
        }
        let ray = self.open.last().map(|&(_, id)| id);
        if let Some(light) = trimmed
            .strip_prefix("lights[")
            .and_then(|rest| rest.split_once("]: ambient"))
            .and_then(|(k, _)| k.parse().ok())
        {
            self.light = Some((light, spaces));
            return (Some("1.4"), ray);
        }
        if let Some((light, _)) = self.light {
            // A light's L, shadow ray and terms: its shadow ray's.
            let shadow =
                self.drawing.rays.iter().find(|r| {
                    r.kind == DrawnKind::Shadow && r.parent == ray && r.light == Some(light)
                });
            return (Some("1.4"), shadow.map(|r| r.id).or(ray));
        }
        (section_of(trimmed), ray)
    }

    /// A line of the path's events, the `k`th.
    fn path_line(&mut self, trimmed: &str, k: usize) -> (Option<&'static str>, Option<usize>) {
        if is_encoding(trimmed) {
            self.path_event = None;
            return (Some("gamma"), None);
        }
        if trimmed.starts_with("... and ") {
            return (Some("path"), None);
        }
        self.path_event = Some(k + 1);
        let traced = self.drawing.rays.iter().find(|r| r.event == Some(k));
        // The first vertex is where the primary ray ends.
        let ray = match traced {
            Some(r) => Some(r.id),
            None if trimmed.starts_with("vertex 0:") => Some(0),
            None => None,
        };
        (Some("path"), ray)
    }
}

/// The lab's section of a line about a ray's hit, its colour or the pixel.
fn section_of(trimmed: &str) -> Option<&'static str> {
    let starts = |prefixes: &[&str]| prefixes.iter().any(|p| trimmed.starts_with(p));
    if starts(&["primary ray (lab 1.2.3)"]) {
        Some("1.2.3")
    } else if starts(&[
        "objects[",
        "missed:",
        "nearest hit:",
        "nothing hit",
        "seen from inside",
    ]) {
        Some("1.3")
    } else if starts(&["local colour", "times the lab texture", "plus its emission"]) {
        Some("1.4")
    } else if starts(&[
        "no mirror or refracted ray",
        "no more rays",
        "... and",
        "times what absorption",
        "colour of this ray",
    ]) {
        Some("1.5")
    } else if is_encoding(trimmed) {
        Some("gamma")
    } else {
        None
    }
}

/// A line of the pixel's sum, saturation and gamma.
fn is_encoding(trimmed: &str) -> bool {
    [
        "this sample's colour",
        "not a finite number",
        "pixel colour (linear)",
        "saturation rule",
        "gamma ",
    ]
    .iter()
    .any(|p| trimmed.starts_with(p))
}
