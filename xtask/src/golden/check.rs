//! Checking renders against their goldens: the outcome of each image, and
//! the table `cargo xtask golden` prints.

use super::cases::Case;
use super::compare::{compare, heat_map, Comparison, SizeMismatch, Tolerance};
use super::manifest::Manifest;
use anyhow::{Context, Result};
use image::RgbImage;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
pub(super) fn read_golden(path: &Path) -> Result<Option<RgbImage>> {
    if !path.exists() {
        return Ok(None);
    }
    let image = image::open(path).with_context(|| format!("{}: cannot read", path.display()))?;
    Ok(Some(image.to_rgb8()))
}

/// The order of the images wherever they are listed (this table, the HTML
/// report): the ones that did not pass first, then the passes, each group
/// in the order of the check (scenes by name, then the lab's other images).
pub fn report_order(results: &[CaseResult]) -> Vec<&CaseResult> {
    let mut order: Vec<&CaseResult> = results.iter().collect();
    // Stable: each group keeps the check's order.
    order.sort_by_key(|r| r.passed());
    order
}

/// The one summary line, in the table's words: "29 images checked: 28 PASS,
/// 1 FAIL" (the verdicts that occur, in the order PASS, FAIL, MISSING, ERROR).
pub fn summary_line(results: &[CaseResult]) -> String {
    let n = results.len();
    let counts: Vec<String> = ["PASS", "FAIL", "MISSING", "ERROR"]
        .iter()
        .map(|v| (v, results.iter().filter(|r| r.verdict() == *v).count()))
        .filter(|&(_, k)| k > 0)
        .map(|(v, k)| format!("{k} {v}"))
        .collect();
    let image = if n == 1 { "image" } else { "images" };
    format!("{n} {image} checked: {}", counts.join(", "))
}

/// The table people read: one row per image, in [`report_order`].
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
    for r in report_order(results) {
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
    out.push_str(&summary_line(results));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::golden::compare::{Comparison, Tolerance};

    fn case(name: &str, outcome: Outcome) -> CaseResult {
        CaseResult {
            name: name.to_string(),
            tolerance: Tolerance::default(),
            outcome,
            golden: None,
            actual: None,
            diff: None,
        }
    }

    fn identical() -> Outcome {
        Outcome::Compared(Comparison {
            pixels: 4,
            differing: 0,
            max_diff: 0,
            mean_diff: 0.0,
        })
    }

    #[test]
    fn one_image_is_one_image() {
        let results = [case("a", identical())];
        assert_eq!(summary_line(&results), "1 image checked: 1 PASS");
    }

    #[test]
    fn the_summary_counts_each_verdict_in_the_tables_words() {
        let results = [
            case("a", identical()),
            case("b", Outcome::MissingGolden),
            case("c", identical()),
            case("d", Outcome::Error("no".into())),
        ];
        assert_eq!(
            summary_line(&results),
            "4 images checked: 2 PASS, 1 MISSING, 1 ERROR"
        );
    }

    #[test]
    fn the_table_lists_what_did_not_pass_first_in_the_checks_order() {
        let results = [
            case("z", identical()),
            case("y", Outcome::MissingGolden),
            case("b", identical()),
            case("a", Outcome::Error("no".into())),
        ];
        let names: Vec<&str> = report_order(&results)
            .iter()
            .map(|r| r.name.as_str())
            .collect();
        assert_eq!(names, ["y", "a", "z", "b"]);
        let table = table(&results);
        let rows: Vec<&str> = table
            .lines()
            .skip(1)
            .filter_map(|l| l.split_whitespace().next())
            .take(4)
            .collect();
        assert_eq!(rows, ["y", "a", "z", "b"]);
    }
}
