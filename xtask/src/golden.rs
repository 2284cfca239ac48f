//! `cargo xtask golden`: every image the project makes, rendered in-process
//! and compared with its reference PNG in `golden/`.

use crate::compare::{compare, heat_map, Comparison, SizeMismatch, Tolerance};
use crate::manifest::Manifest;
use anyhow::{bail, Context, Result};
use image::RgbImage;
use rayon::prelude::*;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tracer_pipeline::{lab, output, Aov, Gamma, Input, Options};

pub type RenderFn = Box<dyn Fn() -> Result<RgbImage> + Send + Sync>;

/// One image with a golden: its name (the golden is `golden/<name>.png`) and
/// how to make it.
pub struct Case {
    pub name: String,
    pub render: RenderFn,
}

impl Case {
    pub fn new(
        name: impl Into<String>,
        render: impl Fn() -> Result<RgbImage> + Send + Sync + 'static,
    ) -> Case {
        Case {
            name: name.into(),
            render: Box::new(render),
        }
    }
}

/// A scene file rendered as `tracer render SCENE` renders it.
pub fn render_scene_file(path: &Path) -> Result<RgbImage> {
    render(path, Options::default())
}

/// A scene file through the pipeline, as the `tracer` command runs it.
fn render(path: &Path, options: Options) -> Result<RgbImage> {
    let loaded = tracer_pipeline::load(&Input::File(path.to_path_buf()))?;
    Ok(tracer_pipeline::render(&loaded, &options, &|_| {})?.image)
}

/// The calibration chart, as `tracer calib-chart [--gamma G]` writes it.
fn render_chart(gamma: Option<f32>) -> Result<RgbImage> {
    let gamma = gamma.map(Gamma::new).transpose()?;
    let (width, height) = lab::DEFAULT_CHART_SIZE;
    Ok(lab::chart(width, height, gamma)?)
}

/// The gamma plot of a measurements CSV, as `tracer gamma fit --plot`.
fn render_gamma_plot(csv: &Path) -> Result<RgbImage> {
    Ok(lab::gamma_plot(&lab::fit_gamma(csv)?)?)
}

/// The lab's images that are not scene renders: its three gradient images
/// (lab names, `tracer render --aov ray-dir-*`), the chart without and with
/// gamma, and the sample gamma plot.
pub fn lab_image_cases(root: &Path) -> Vec<Case> {
    let lab_camera = root.join("scenes/sphere-intersection.toml");
    let mut cases: Vec<Case> = [
        ("gradient-OX", Aov::RayDirX),
        ("gradient-OY", Aov::RayDirY),
        ("gradient-OZ", Aov::RayDirZ),
    ]
    .into_iter()
    .map(|(name, aov)| {
        let path = lab_camera.clone();
        let options = Options {
            aov: Some(aov),
            ..Options::default()
        };
        Case::new(name, move || render(&path, options))
    })
    .collect();
    cases.push(Case::new("calib-chart", || render_chart(None)));
    cases.push(Case::new("calib-chart-gamma-2.2", || {
        render_chart(Some(2.2))
    }));
    let csv = root.join("scenes/gamma/sample-measurements.csv");
    cases.push(Case::new("gamma-plot", move || render_gamma_plot(&csv)));
    cases
}

/// Every image checked against a golden. New kinds of images join the list here.
pub fn all_cases(root: &Path) -> Result<Vec<Case>> {
    let mut cases = scene_cases(&root.join("scenes"))?;
    cases.extend(lab_image_cases(root));
    check_unique(&cases)?;
    Ok(cases)
}

/// One case per `*.toml` scene file in `dir`, named by its file stem, in name order.
pub fn scene_cases(dir: &Path) -> Result<Vec<Case>> {
    let mut paths = Vec::new();
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot read {}", dir.display()))? {
        let path = entry
            .with_context(|| format!("cannot read {}", dir.display()))?
            .path();
        if path.extension().is_some_and(|e| e == "toml") {
            paths.push(path);
        }
    }
    let mut cases = paths
        .into_iter()
        .map(|path| {
            let name = file_stem(&path)?;
            Ok(Case::new(name, move || render_scene_file(&path)))
        })
        .collect::<Result<Vec<_>>>()?;
    cases.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(cases)
}

fn file_stem(path: &Path) -> Result<String> {
    path.file_stem()
        .and_then(|s| s.to_str())
        .map(str::to_string)
        .with_context(|| format!("{}: the file name is not UTF-8", path.display()))
}

fn check_unique(cases: &[Case]) -> Result<()> {
    let mut seen = BTreeSet::new();
    for case in cases {
        if !seen.insert(case.name.as_str()) {
            bail!(
                "two images are named {:?}: their goldens would clash",
                case.name
            );
        }
    }
    Ok(())
}

/// Only the named cases (all when `names` is empty); an unknown name is an error.
pub fn select(cases: Vec<Case>, names: &[String]) -> Result<Vec<Case>> {
    if names.is_empty() {
        return Ok(cases);
    }
    let known: BTreeSet<&str> = cases.iter().map(|c| c.name.as_str()).collect();
    let unknown: Vec<&str> = names
        .iter()
        .map(String::as_str)
        .filter(|n| !known.contains(n))
        .collect();
    if !unknown.is_empty() {
        bail!(
            "no image named {}; known: {}",
            unknown.join(", "),
            known.into_iter().collect::<Vec<_>>().join(", ")
        );
    }
    Ok(cases
        .into_iter()
        .filter(|c| names.contains(&c.name))
        .collect())
}

/// What checking one image found.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    Compared(Comparison),
    SizeMismatch(SizeMismatch),
    /// No `golden/<name>.png` yet.
    MissingGolden,
    /// The render failed, or the golden could not be read.
    Error(String),
}

/// One image checked, with the pictures the report shows.
pub struct CaseResult {
    pub name: String,
    pub tolerance: Tolerance,
    pub outcome: Outcome,
    pub golden: Option<RgbImage>,
    pub actual: Option<RgbImage>,
    pub diff: Option<RgbImage>,
}

impl CaseResult {
    pub fn passed(&self) -> bool {
        matches!(&self.outcome, Outcome::Compared(c) if c.passes(&self.tolerance))
    }

    /// PASS, FAIL, MISSING or ERROR.
    pub fn verdict(&self) -> &'static str {
        match &self.outcome {
            _ if self.passed() => "PASS",
            Outcome::Compared(_) | Outcome::SizeMismatch(_) => "FAIL",
            Outcome::MissingGolden => "MISSING",
            Outcome::Error(_) => "ERROR",
        }
    }

    /// Why it did not pass, for people; `None` when it passed.
    pub fn problem(&self) -> Option<String> {
        match &self.outcome {
            _ if self.passed() => None,
            Outcome::Compared(c) => Some(format!(
                "{:.3} % of pixels differ by more than {}/255 (allowed: {} %)",
                c.differing_percent(),
                self.tolerance.channel,
                self.tolerance.max_differing_percent
            )),
            Outcome::SizeMismatch(m) => Some(m.to_string()),
            Outcome::MissingGolden => Some(format!(
                "no golden image golden/{}.png; look at the render, then: cargo xtask golden --bless {}",
                self.name, self.name
            )),
            Outcome::Error(e) => Some(e.clone()),
        }
    }
}

/// Renders the cases in parallel and compares each with `golden_dir/<name>.png`.
pub fn check(cases: &[Case], golden_dir: &Path, manifest: &Manifest) -> Vec<CaseResult> {
    cases
        .par_iter()
        .map(|case| check_one(case, golden_dir, manifest.tolerance(&case.name)))
        .collect()
}

fn check_one(case: &Case, golden_dir: &Path, tolerance: Tolerance) -> CaseResult {
    let mut result = CaseResult {
        name: case.name.clone(),
        tolerance,
        outcome: Outcome::MissingGolden,
        golden: None,
        actual: None,
        diff: None,
    };
    let actual = match (case.render)() {
        Ok(image) => image,
        Err(e) => {
            result.outcome = Outcome::Error(format!("render failed: {e:#}"));
            return result;
        }
    };
    let golden_path = golden_path(golden_dir, &case.name);
    match read_golden(&golden_path) {
        Ok(Some(golden)) => {
            result.outcome = match compare(&golden, &actual, &tolerance) {
                Ok(c) => Outcome::Compared(c),
                Err(m) => Outcome::SizeMismatch(m),
            };
            result.diff = heat_map(&golden, &actual, &tolerance).ok();
            result.golden = Some(golden);
        }
        Ok(None) => result.outcome = Outcome::MissingGolden,
        Err(e) => result.outcome = Outcome::Error(format!("{e:#}")),
    }
    result.actual = Some(actual);
    result
}

pub fn golden_path(golden_dir: &Path, name: &str) -> PathBuf {
    golden_dir.join(format!("{name}.png"))
}

/// The golden image, or `None` when there is none yet.
fn read_golden(path: &Path) -> Result<Option<RgbImage>> {
    if !path.exists() {
        return Ok(None);
    }
    let image = image::open(path).with_context(|| format!("{}: cannot read", path.display()))?;
    Ok(Some(image.to_rgb8()))
}

/// The table people read: one row per image.
pub fn table(results: &[CaseResult]) -> String {
    let width = results
        .iter()
        .map(|r| r.name.len())
        .chain([5])
        .max()
        .unwrap_or(5);
    let mut out = format!(
        "{:<width$}  {:>18}  {:>8}  {:>9}  result\n",
        "image", "pixels differing", "max diff", "mean diff"
    );
    for r in results {
        let numbers = match &r.outcome {
            Outcome::Compared(c) => format!(
                "{:>9} {:>7.3}%  {:>8}  {:>9.4}",
                c.differing,
                c.differing_percent(),
                c.max_diff,
                c.mean_diff
            ),
            _ => format!("{:>18}  {:>8}  {:>9}", "-", "-", "-"),
        };
        let _ = write!(out, "{:<width$}  {numbers}  {}", r.name, r.verdict());
        if let Some(problem) = r.problem() {
            let _ = write!(out, ": {problem}");
        }
        out.push('\n');
    }
    let failed = results.iter().filter(|r| !r.passed()).count();
    let _ = write!(
        out,
        "{} images: {} passed, {failed} not",
        results.len(),
        results.len() - failed
    );
    out
}

/// A whole check as `cargo xtask golden` runs it.
pub struct Summary {
    pub results: Vec<CaseResult>,
    pub table: String,
    pub report: PathBuf,
}

impl Summary {
    pub fn all_passed(&self) -> bool {
        self.results.iter().all(CaseResult::passed)
    }
}

/// Checks the named images (all when `names` is empty) of the workspace at
/// `root` and writes the report to `report_dir`.
pub fn run_check(root: &Path, names: &[String], report_dir: &Path) -> Result<Summary> {
    let golden_dir = root.join("golden");
    let cases = all_cases(root)?;
    let manifest = load_manifest(&golden_dir, &cases)?;
    let cases = select(cases, names)?;
    let results = check(&cases, &golden_dir, &manifest);
    let report = crate::report::write(report_dir, &results)?;
    Ok(Summary {
        table: table(&results),
        results,
        report,
    })
}

fn load_manifest(golden_dir: &Path, cases: &[Case]) -> Result<Manifest> {
    let path = golden_dir.join("golden.toml");
    let manifest = Manifest::load(&path)?;
    manifest.check_names(&path, |n| cases.iter().any(|c| c.name == n))?;
    Ok(manifest)
}

/// What blessing did to one golden.
#[derive(Debug, Clone, PartialEq)]
pub enum Blessed {
    New {
        name: String,
        size: (u32, u32),
    },
    /// Rewritten; `change` counts every pixel that is not identical.
    Changed {
        name: String,
        change: Comparison,
    },
    Resized {
        name: String,
        change: SizeMismatch,
    },
    /// The old golden could not be read; it was replaced.
    Unreadable {
        name: String,
        error: String,
    },
    Unchanged {
        name: String,
    },
}

impl std::fmt::Display for Blessed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Blessed::New { name, size: (w, h) } => write!(f, "new        {name} ({w}x{h})"),
            Blessed::Changed { name, change: c } => write!(
                f,
                "changed    {name}: {} of {} pixels ({:.3} %), max diff {}, mean diff {:.4}",
                c.differing,
                c.pixels,
                c.differing_percent(),
                c.max_diff,
                c.mean_diff
            ),
            Blessed::Resized { name, change } => write!(f, "changed    {name}: {change}"),
            Blessed::Unreadable { name, error } => {
                write!(
                    f,
                    "replaced   {name}: the old golden was unreadable ({error})"
                )
            }
            Blessed::Unchanged { name } => write!(f, "unchanged  {name}"),
        }
    }
}

/// Renders the cases and makes each the golden in `golden_dir`; a golden whose
/// pixels are already identical is left as it is. Nothing is written unless
/// every render succeeded.
pub fn bless(cases: &[Case], golden_dir: &Path) -> Result<Vec<Blessed>> {
    let renders: Vec<(&Case, RgbImage)> = cases
        .par_iter()
        .map(|case| {
            let image = (case.render)().with_context(|| format!("{}: render failed", case.name))?;
            Ok((case, image))
        })
        .collect::<Result<_>>()?;
    std::fs::create_dir_all(golden_dir)
        .with_context(|| format!("cannot create {}", golden_dir.display()))?;
    renders
        .iter()
        .map(|(case, image)| bless_one(&case.name, image, golden_dir))
        .collect()
}

fn bless_one(name: &str, image: &RgbImage, golden_dir: &Path) -> Result<Blessed> {
    let path = golden_path(golden_dir, name);
    let exact = Tolerance {
        channel: 0,
        max_differing_percent: 0.0,
    };
    let name = name.to_string();
    let blessed = match read_golden(&path) {
        Ok(None) => Blessed::New {
            name,
            size: image.dimensions(),
        },
        Err(e) => Blessed::Unreadable {
            name,
            error: format!("{e:#}"),
        },
        Ok(Some(old)) => match compare(&old, image, &exact) {
            Ok(c) if c.differing == 0 => return Ok(Blessed::Unchanged { name }),
            Ok(change) => Blessed::Changed { name, change },
            Err(change) => Blessed::Resized { name, change },
        },
    };
    output::write_image(image, &path)?;
    Ok(blessed)
}

/// `cargo xtask golden --bless [NAME...]` for the workspace at `root`.
pub fn run_bless(root: &Path, names: &[String]) -> Result<Vec<Blessed>> {
    let cases = select(all_cases(root)?, names)?;
    bless(&cases, &root.join("golden"))
}
