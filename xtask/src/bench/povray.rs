//! POV-Ray 3.7, the classic CPU ray tracer: its render-only time on the
//! same scene, written as POV-Ray SDL by `pov_scene`.

use super::pov_scene::pov_scene;
use super::stats::median;
use super::THREADS;
use anyhow::{bail, Context, Result};
use scene_format::SceneFile;
use std::path::Path;
use std::process::Command;

/// POV-Ray's figures on one scene: medians over the runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PovRay {
    /// "Trace Time" on 1 and 2 threads: render only, without start-up and
    /// parsing.
    pub wall_s: [f64; 2],
    /// CPU-seconds of the 1-thread trace.
    pub cpu_s: f64,
}

/// Whether `povray` runs; if not, one line saying that it is skipped.
pub fn available() -> bool {
    let found = Command::new("povray")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success() || !o.stderr.is_empty());
    if !found {
        eprintln!("POV-Ray: skipped, `povray` not found (apt-get install povray)");
    }
    found
}

/// Writes `scene` as `NAME.pov` and times POV-Ray on it, `reps` times on
/// each thread count. The .pov file and POV-Ray's `NAME.png` go to `keep`
/// when given, else to a temporary folder.
pub fn measure(scene: &SceneFile, name: &str, reps: usize, keep: Option<&Path>) -> Result<PovRay> {
    let temp = tempfile::tempdir()?;
    let dir = match keep {
        Some(dir) => {
            std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
            dir
        }
        None => temp.path(),
    };
    let pov = dir.join(format!("{name}.pov"));
    std::fs::write(&pov, pov_scene(scene)).with_context(|| format!("write {}", pov.display()))?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let (mut wall_s, mut cpu_s) = ([0.0; 2], 0.0);
    for (t, &threads) in THREADS.iter().enumerate() {
        let (mut walls, mut cpus) = (Vec::new(), Vec::new());
        for _ in 0..reps {
            let (w, c) = trace_time(&pov, w, h, threads)?;
            walls.push(w);
            cpus.push(c);
        }
        wall_s[t] = median(walls);
        if threads == 1 {
            cpu_s = median(cpus);
        }
    }
    Ok(PovRay { wall_s, cpu_s })
}

/// Runs POV-Ray once (no anti-aliasing, no display), its image next to the
/// .pov file, and reads its own "Trace Time": wall and CPU seconds.
fn trace_time(pov: &Path, w: u32, h: u32, threads: usize) -> Result<(f64, f64)> {
    let dir = pov.parent().context("the .pov file's folder")?;
    let out = Command::new("povray")
        .arg(format!("+I{}", pov.display()))
        .arg(format!("+O{}", pov.with_extension("png").display()))
        .args([format!("+W{w}"), format!("+H{h}")])
        .args(["-D", "-A", "-P", "+V"])
        .arg(format!("+WT{threads}"))
        .current_dir(dir)
        .output()
        .context("run povray")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        bail!("povray failed: {stderr}");
    }
    parse_trace_time(&stderr)
        .with_context(|| format!("no Trace Time in povray's output:\n{stderr}"))
}

/// "Trace Time:       0 hours  0 minutes  1 seconds (1.659 seconds)" and
/// the next line, "using 1 thread(s) with 1.427 CPU-seconds total".
fn parse_trace_time(text: &str) -> Option<(f64, f64)> {
    let mut lines = text
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("Trace Time:"));
    let wall = lines.next()?.rsplit_once('(')?.1;
    let wall = wall.split_whitespace().next()?.parse().ok()?;
    let cpu = lines.next()?.split(" with ").nth(1)?;
    let cpu = cpu.split_whitespace().next()?.parse().ok()?;
    Some((wall, cpu))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn povray_trace_time_is_read_from_its_statistics() {
        let text = "Render Time:\n  Photon Time:      No photons\n  \
                    Radiosity Time:   No radiosity\n  \
                    Trace Time:       0 hours  0 minutes  1 seconds (1.659 seconds)\n  \
                    using 1 thread(s) with 1.427 CPU-seconds total\n";
        assert_eq!(parse_trace_time(text), Some((1.659, 1.427)));
        assert_eq!(parse_trace_time("nothing"), None);
    }
}
