//! Every image that has a golden, and how each is made: through the
//! pipeline, exactly as the `tracer` command makes it.

use anyhow::{bail, Context, Result};
use image::RgbImage;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use tracer_pipeline::{lab, Aov, Gamma, Input, Options};

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
    Ok(tracer_pipeline::render(&loaded, &options, &|_| {})?
        .image
        .to_rgb8())
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

/// One case per `*.toml` scene file in `dir` and its folders, in name
/// order, named by its path below `dir` without the extension, `-` for each
/// `/`: `bench/bunny.toml` is `bench-bunny` (`check_unique` catches a clash
/// with a `bench-bunny.toml`).
pub fn scene_cases(dir: &Path) -> Result<Vec<Case>> {
    let cases = scene_files(dir)?
        .into_iter()
        .map(|(name, path)| Case::new(name, move || render_scene_file(&path)))
        .collect();
    Ok(cases)
}

/// Every `*.toml` file in `dir` and its folders with its case name, in name order.
pub fn scene_files(dir: &Path) -> Result<Vec<(String, PathBuf)>> {
    let mut files = Vec::new();
    collect_scene_files(dir, "", &mut files)?;
    files.sort();
    Ok(files)
}

fn collect_scene_files(dir: &Path, prefix: &str, out: &mut Vec<(String, PathBuf)>) -> Result<()> {
    let read_error = || format!("cannot read {}", dir.display());
    for entry in std::fs::read_dir(dir).with_context(read_error)? {
        let path = entry.with_context(read_error)?.path();
        if path.is_dir() {
            let sub = format!("{prefix}{}-", file_name(&path)?);
            collect_scene_files(&path, &sub, out)?;
        } else if path.extension().is_some_and(|e| e == "toml") {
            out.push((format!("{prefix}{}", file_stem(&path)?), path));
        }
    }
    Ok(())
}

fn file_stem(path: &Path) -> Result<String> {
    utf8(path, path.file_stem())
}

fn file_name(path: &Path) -> Result<String> {
    utf8(path, path.file_name())
}

fn utf8(path: &Path, part: Option<&std::ffi::OsStr>) -> Result<String> {
    part.and_then(|s| s.to_str())
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
