//! `cargo xtask golden`: every image the project makes, rendered in-process
//! and compared with its reference PNG in `golden/`; the HTML report
//! (`report.rs`), which `xtask/tests/browser.rs` loads in headless Chromium.

pub mod bless;
pub mod cases;
pub mod check;
pub mod compare;
pub mod manifest;
pub mod report;

pub use bless::{bless, run_bless, Blessed};
pub use cases::{
    all_cases, lab_image_cases, render_scene_file, scene_cases, scene_files, select, Case,
};
pub use check::{check, golden_path, table, CaseResult, Outcome, Summary};

use anyhow::Result;
use manifest::Manifest;
use std::path::Path;

/// Checks the named images (all when `names` is empty) of the workspace at
/// `root` and writes the report to `report_dir`.
pub fn run_check(root: &Path, names: &[String], report_dir: &Path) -> Result<Summary> {
    let golden_dir = root.join("golden");
    let cases = all_cases(root)?;
    let manifest = load_manifest(&golden_dir, &cases)?;
    let cases = select(cases, names)?;
    let results = check(&cases, &golden_dir, &manifest);
    let report = report::write(report_dir, &results)?;
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
