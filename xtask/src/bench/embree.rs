//! Embree 3, the reference for CPU ray traversal: the harness
//! `xtask/peers/embree_bench.cpp` (medium-quality BVH, `rtcIntersect1` +
//! `rtcOccluded1` + Lambert shade, the bunny scene's camera and light),
//! compiled into `target/peers/` when `g++` and `libembree-dev` are there.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The harness's source, relative to the workspace root.
const SOURCE: &str = "xtask/peers/embree_bench.cpp";
const HEADER: &str = "/usr/include/embree3/rtcore.h";

/// Embree's figures for one mesh scene (medium-quality BVH).
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub struct Embree {
    pub build_s: [f64; 2],
    /// Primary + shadow + shade, Mrays/s.
    pub mrays: [f64; 2],
}

/// The harness compiled into `out_dir`, rebuilt when its source is newer;
/// None, after one line saying why, when it cannot be built.
pub fn build(root: &Path, out_dir: &Path) -> Option<PathBuf> {
    let source = root.join(SOURCE);
    let exe = out_dir.join("embree_bench");
    let skipped = || {
        eprintln!(
            "Embree: skipped, needs g++ and libembree-dev (apt-get install g++ libembree-dev)"
        );
        None
    };
    // Checked first: a harness built before Embree was uninstalled cannot
    // load its library.
    if !Path::new(HEADER).is_file() {
        return skipped();
    }
    if is_newer(&exe, &source) {
        return Some(exe);
    }
    let gxx = Command::new("g++").arg("--version").output();
    if !gxx.is_ok_and(|o| o.status.success()) {
        return skipped();
    }
    eprintln!("bench: compiling {} ...", source.display());
    let built = std::fs::create_dir_all(out_dir).and_then(|()| {
        Command::new("g++")
            .args(["-O3", "-march=native", "-std=c++17"])
            .arg(&source)
            .arg("-o")
            .arg(&exe)
            .args(["-lembree3", "-lpthread"])
            .output()
    });
    match built {
        Ok(out) if out.status.success() => Some(exe),
        Ok(out) => {
            let why = String::from_utf8_lossy(&out.stderr);
            let first = why.lines().next().unwrap_or("");
            eprintln!(
                "Embree: skipped, {} did not compile: {first}",
                source.display()
            );
            None
        }
        Err(e) => {
            eprintln!("Embree: skipped, could not run g++: {e}");
            None
        }
    }
}

/// Whether `a` exists and was modified no earlier than `b`.
fn is_newer(a: &Path, b: &Path) -> bool {
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    match (modified(a), modified(b)) {
        (Some(a), Some(b)) => a >= b,
        _ => false,
    }
}

/// Runs the harness on `obj` split `subdiv` times, `reps` frames each.
pub fn measure(exe: &Path, obj: &Path, subdiv: u32, reps: usize) -> Result<Embree> {
    let text = super::process::stdout_of(
        Command::new(exe).arg(obj).args([
            "--reps",
            &reps.to_string(),
            "--subdiv",
            &subdiv.to_string(),
        ]),
        "embree_bench",
    )?;
    parse(&text).with_context(|| format!("unexpected embree_bench output:\n{text}"))
}

/// Reads the medium-quality sections of embree_bench's report.
fn parse(text: &str) -> Option<Embree> {
    let mut e = Embree::default();
    let mut found = [false; 2];
    let mut section = None;
    for line in text.lines() {
        if line.starts_with('[') {
            section = match line {
                l if l.starts_with("[quality=medium threads=1]") => Some(0),
                l if l.starts_with("[quality=medium threads=2]") => Some(1),
                _ => None,
            };
            if let Some(t) = section {
                let ms = line.split("median").nth(1)?.split_whitespace().next()?;
                e.build_s[t] = ms.parse::<f64>().ok()? / 1e3;
            }
        } else if let (Some(t), true) = (section, line.contains("+ shade")) {
            let before = line.split("Mrays/s").next()?;
            e.mrays[t] = before.split_whitespace().last()?.parse().ok()?;
            found[t] = true;
        }
    }
    (found == [true, true]).then_some(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embree_figures_are_read_from_its_report() {
        let text = "[quality=medium threads=1] BVH build (rtcCommitScene) median 63.9 ms  (1.09 Mtris/s)\n\
            primary rtcIntersect1   232.25 ms/frame      8.93 Mrays/s  (hits 510496 = 24.6%)\n\
            primary1 + shadow rtcOccluded1 + shade   357.65 ms/frame      7.13 Mrays/s  (hits)\n\
            [quality=medium threads=2] BVH build (rtcCommitScene) median 48.7 ms  (1.43 Mtris/s)\n\
            primary1 + shadow rtcOccluded1 + shade   200.00 ms/frame     12.50 Mrays/s  (hits)\n\
            [quality=high threads=1] BVH build (rtcCommitScene) median 256.6 ms  (0.27 Mtris/s)\n\
            primary1 + shadow rtcOccluded1 + shade   361.86 ms/frame      7.05 Mrays/s  (hits)\n";
        let e = parse(text).expect("parsed");
        assert_eq!(e.build_s, [0.0639, 0.0487]);
        assert_eq!(e.mrays, [7.13, 12.5]);
        assert!(parse("[quality=medium threads=1] nothing").is_none());
    }
}
