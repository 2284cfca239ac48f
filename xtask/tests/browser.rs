//! The report opened in a real browser: headless Chromium loads
//! `index.html` from disk, and every image on it must load.

use headless::{dump_dom, image_check, ImageCheck};
use image::{Rgb, RgbImage};
use std::path::{Path, PathBuf};
use std::time::Duration;
use xtask::golden::manifest::Manifest;
use xtask::golden::{self, Case};

const TIMEOUT: Duration = Duration::from_secs(120);

/// Chromium, or `None` with a notice (an error under CI).
fn chromium() -> Option<PathBuf> {
    headless::chromium_for_test("the browser check of the golden report")
}

fn load(chromium: &Path, index: &Path) -> ImageCheck {
    let dom = dump_dom(chromium, index, TIMEOUT).unwrap();
    image_check(&dom).unwrap_or_else(|e| panic!("{e:#}\n{dom}"))
}

#[test]
fn every_image_of_the_golden_report_loads_in_chromium() {
    let Some(chromium) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let summary =
        golden::run_check(&xtask::workspace_root(), &[], &dir.path().join("golden")).unwrap();
    let check = load(&chromium, &summary.report);
    // golden, actual and difference for every image
    let expected = 3 * golden::all_cases(&xtask::workspace_root()).unwrap().len();
    assert_eq!(
        check,
        ImageCheck {
            total: expected,
            loaded: expected,
            failed: vec![]
        }
    );
}

#[test]
fn the_browser_check_notices_an_image_that_does_not_load() {
    let Some(chromium) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let golden_dir = dir.path().join("golden");
    let red = RgbImage::from_pixel(8, 6, Rgb([200, 0, 0]));
    let cases = [Case::new("odd name #1", move || Ok(red.clone()))];
    golden::bless(&cases, &golden_dir).unwrap();
    let results = golden::check(&cases, &golden_dir, &Manifest::default());
    let report = dir.path().join("report");
    let index = xtask::golden::report::write(&report, &results).unwrap();

    assert_eq!(
        load(&chromium, &index),
        ImageCheck {
            total: 3,
            loaded: 3,
            failed: vec![]
        }
    );
    std::fs::remove_file(report.join("odd name #1-diff.png")).unwrap();
    assert_eq!(
        load(&chromium, &index),
        ImageCheck {
            total: 3,
            loaded: 2,
            failed: vec!["odd%20name%20%231-diff.png".to_string()]
        }
    );
}
