//! The path tracer's peers on a bench scene: Mitsuba 3 and Blender Cycles,
//! run by the scene's script in `xtask/peers/` at a given samples per pixel
//! and thread count (its render-only seconds and its EXR), the RMSE between two images,
//! and, at equal time, the RMSE a peer reaches within a time budget and the
//! time it takes to reach a given RMSE.

use anyhow::{bail, Context, Result};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// A scene the path tracer is measured on, with the script that renders
/// it in the peers and the peers' reference image (paths relative to the
/// workspace root; the reference's README says how it was made).
#[derive(Debug, Clone, Copy)]
pub struct BenchScene {
    /// What the report's heading says of it.
    pub title: &'static str,
    pub scene: &'static str,
    /// The peers' script and the arguments before its command (paths):
    /// `toml_scene.py` takes the scene file, whose Mitsuba scene it builds.
    pub script: &'static [&'static str],
    pub reference: &'static str,
    /// Its reference's own noise, as an RMSE.
    pub reference_noise: f64,
    /// The RMSE whose time to reach is reported: one the renderers reach
    /// near the time budget, where reading it off needs little
    /// extrapolation.
    pub target_rmse: f64,
    /// The peers its script renders it in, beside `Peer::MITSUBA`'s: its
    /// `--all-peers` ones.
    pub more_peers: &'static [Peer],
}

/// Mitsuba 3's Cornell box.
pub const CORNELL_BOX: BenchScene = BenchScene {
    title: "Mitsuba 3's Cornell box, 256x256, max depth 7 (Mitsuba's 8, Cycles' 6 bounces)",
    scene: "scenes/cornell-box.toml",
    script: &["xtask/peers/cornell.py"],
    reference: "crates/tracer-core/tests/data/cornell-box-mitsuba.exr",
    reference_noise: 0.0004,
    target_rmse: 0.01,
    more_peers: &[Peer::SCALAR, Peer::Cycles],
};

/// Rough and smooth metal and glass under a studio environment.
pub const MATERIALS: BenchScene = BenchScene {
    title: "scenes/materials.toml, 480x240, rough metal and glass in an environment, max depth 8 (Mitsuba's 9)",
    scene: "scenes/materials.toml",
    script: &["xtask/peers/toml_scene.py", "scenes/materials.toml"],
    reference: "crates/tracer-core/tests/data/materials-mitsuba.exr",
    reference_noise: 0.0061,
    target_rmse: 0.08,
    more_peers: &[Peer::SCALAR],
};

/// A 70k-triangle mesh and a glossy ball in a room lit by one lamp.
pub const CORNELL_BUNNY: BenchScene = BenchScene {
    title: "scenes/cornell-bunny.toml, 256x256, the bunny (69,666 triangles) and rough gold in the Cornell box, max depth 7 (Mitsuba's 8)",
    scene: "scenes/cornell-bunny.toml",
    script: &["xtask/peers/toml_scene.py", "scenes/cornell-bunny.toml"],
    reference: "crates/tracer-core/tests/data/cornell-bunny-mitsuba.exr",
    reference_noise: 0.0012,
    target_rmse: 0.02,
    more_peers: &[Peer::SCALAR],
};

/// Image textures under an HDR sky with a sun.
pub const COURTYARD: BenchScene = BenchScene {
    title: "scenes/courtyard.toml, 320x240, textured floor and crate and rough copper under an HDR sky with a sun, max depth 7 (Mitsuba's 8)",
    scene: "scenes/courtyard.toml",
    script: &["xtask/peers/toml_scene.py", "scenes/courtyard.toml"],
    reference: "crates/tracer-core/tests/data/courtyard-mitsuba.exr",
    reference_noise: 0.0025,
    target_rmse: 0.05,
    more_peers: &[Peer::SCALAR],
};

/// The script's exit status for a renderer that is not installed (its one
/// line on stderr says which, and how to install it).
const NOT_INSTALLED: i32 = 3;

/// One peer renderer and its settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Peer {
    /// Mitsuba 3: `llvm_ad_rgb` or `scalar_rgb`, sampler `independent` or
    /// `multijitter`.
    Mitsuba {
        variant: &'static str,
        sampler: &'static str,
    },
    /// Blender Cycles on the CPU (`bpy`).
    Cycles,
}

impl Peer {
    /// The peers every scene is measured against: Mitsuba 3's vectorised
    /// variant with each of its two samplers (issue 53's "best Mitsuba
    /// sampler" is the better of these two at equal time).
    pub const MITSUBA: [Peer; 2] = [
        Peer::Mitsuba {
            variant: "llvm_ad_rgb",
            sampler: "independent",
        },
        Peer::Mitsuba {
            variant: "llvm_ad_rgb",
            sampler: "multijitter",
        },
    ];

    /// Mitsuba 3's scalar variant: one path at a time.
    pub const SCALAR: Peer = Peer::Mitsuba {
        variant: "scalar_rgb",
        sampler: "independent",
    };

    pub fn name(&self) -> String {
        match self {
            Peer::Mitsuba { variant, sampler } => format!("Mitsuba 3 {variant} {sampler}"),
            Peer::Cycles => "Cycles".into(),
        }
    }

    /// The Python module the peer's script imports, and the pip packages
    /// that provide it (and what the script needs beside it).
    fn python_module(&self) -> (&'static str, &'static [&'static str]) {
        match self {
            Peer::Mitsuba { .. } => ("mitsuba", &["mitsuba", "numpy"]),
            Peer::Cycles => ("bpy", &["bpy"]),
        }
    }

    fn args(&self) -> Vec<&'static str> {
        match *self {
            Peer::Mitsuba { variant, sampler } => {
                vec!["mitsuba", "--variant", variant, "--sampler", sampler]
            }
            Peer::Cycles => vec!["cycles"],
        }
    }
}

/// How the script is started: `python3 xtask/peers/cornell.py`, say (tests
/// put a stand-in in its place).
#[derive(Debug, Clone)]
pub struct Runner {
    pub program: PathBuf,
    pub args: Vec<String>,
    /// A run taking longer is stopped and is an error: a peer that hangs
    /// (Mitsuba 3.9 did, writing its EXR on one thread) must not hang the
    /// bench.
    pub timeout: Duration,
}

impl Runner {
    /// `python3` on `script`: the script and its first arguments, paths
    /// from `root`.
    pub fn new(root: &Path, script: &[&str]) -> Runner {
        Runner {
            program: "python3".into(),
            args: script
                .iter()
                .map(|part| root.join(part).to_string_lossy().into_owned())
                .collect(),
            timeout: Duration::from_secs(600),
        }
    }
}

/// Installs with pip the Python module of each of `peers` that `python3`
/// cannot import. One that cannot be installed (no pip, no network, a
/// Python its wheels do not support) is said in one line; its runs are then
/// skipped by the script's own line.
pub fn install_missing(peers: &[Peer]) {
    let mut tried = Vec::new();
    for peer in peers {
        let (module, packages) = peer.python_module();
        if tried.contains(&module) {
            continue;
        }
        tried.push(module);
        let mut import = Command::new("python3");
        import.args(["-c", &format!("import {module}")]);
        if matches!(output_within(&mut import, Duration::from_secs(60)), Ok((s, ..)) if s.success())
        {
            continue;
        }
        eprintln!(
            "bench: {} is missing: pip install {} ...",
            peer.name(),
            packages.join(" ")
        );
        let mut pip = Command::new("python3");
        pip.args(["-m", "pip", "install", "--quiet"]).args(packages);
        match output_within(&mut pip, Duration::from_secs(1200)) {
            Ok((status, ..)) if status.success() => {}
            Ok((status, _, stderr)) => eprintln!(
                "bench: pip install {} failed ({status}): {}",
                packages.join(" "),
                stderr.trim_end().lines().last().unwrap_or("")
            ),
            Err(e) => eprintln!("bench: pip install {}: {e:#}", packages.join(" ")),
        }
    }
}

/// A linear RGB image, row by row from the top, three floats a pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct FloatImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<f32>,
}

/// An EXR's (or any format's) colour channels as linear floats.
pub fn read_image(path: &Path) -> Result<FloatImage> {
    let image = image::open(path)
        .with_context(|| format!("cannot read {}", path.display()))?
        .into_rgb32f();
    Ok(FloatImage {
        width: image.width(),
        height: image.height(),
        rgb: image.into_raw(),
    })
}

/// Root mean square of the difference over every pixel and channel.
pub fn rmse(a: &FloatImage, b: &FloatImage) -> Result<f64> {
    if (a.width, a.height) != (b.width, b.height) {
        bail!(
            "images of different sizes: {}x{} and {}x{}",
            a.width,
            a.height,
            b.width,
            b.height
        );
    }
    let sum: f64 = a
        .rgb
        .iter()
        .zip(&b.rgb)
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).powi(2))
        .sum();
    Ok((sum / a.rgb.len() as f64).sqrt())
}

/// One render of a peer.
#[derive(Debug, Clone)]
pub struct Run {
    /// The samples per pixel rendered: Mitsuba's multijitter rounds some
    /// counts up (128 to 132).
    pub spp: u32,
    /// The render alone: without start-up, scene loading, kernel loading
    /// and JIT compilation.
    pub seconds: f64,
    /// CPU seconds of the render (about threads x seconds).
    pub cpu_s: f64,
    pub image: FloatImage,
}

/// Renders the runner's scene with `peer` into `dir`; None, after the
/// script's one line saying why, when the peer is not installed.
pub fn run(
    runner: &Runner,
    peer: Peer,
    spp: u32,
    threads: usize,
    seed: u32,
    dir: &Path,
) -> Result<Option<Run>> {
    let out = dir.join(format!(
        "{}-{spp}spp-{threads}t-{seed}.exr",
        peer.name().replace(' ', "-")
    ));
    let mut command = Command::new(&runner.program);
    command
        .args(&runner.args)
        .args(peer.args())
        .arg("--spp")
        .arg(spp.to_string())
        .arg("--threads")
        .arg(threads.to_string())
        .arg("--seed")
        .arg(seed.to_string())
        .arg("--out")
        .arg(&out);
    let (status, stdout, stderr) = output_within(&mut command, runner.timeout)
        .with_context(|| format!("{} ({})", peer.name(), runner.program.display()))?;
    if status.code() == Some(NOT_INSTALLED) {
        eprintln!("{}", stderr.trim_end().lines().last().unwrap_or(""));
        return Ok(None);
    }
    if !status.success() {
        bail!("{} failed ({status}): {stderr}", peer.name());
    }
    let line = stdout.lines().last().unwrap_or("");
    let field = |key| {
        json_number(line, key)
            .with_context(|| format!("{}: no `{key}` in its output line {line:?}", peer.name()))
    };
    Ok(Some(Run {
        spp: field("spp")? as u32,
        seconds: field("seconds")?,
        cpu_s: field("cpu_s")?,
        image: read_image(&out)?,
    }))
}

/// The command's status, stdout and stderr, as `Command::output`, but
/// killed (and an error) after `timeout`.
fn output_within(command: &mut Command, timeout: Duration) -> Result<(ExitStatus, String, String)> {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .context("cannot start")?;
    // Read as it comes, so a full pipe never stalls the child.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_string(&mut text);
            }
            text
        })
    };
    let stdout = drain(child.stdout.take().map(|p| Box::new(p) as _));
    let stderr = drain(child.stderr.take().map(|p| Box::new(p) as _));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break status;
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            bail!("stopped after {} s", timeout.as_secs_f64());
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let text = |t: std::thread::JoinHandle<String>| t.join().unwrap_or_default();
    Ok((status, text(stdout), text(stderr)))
}

/// The number of `"key": NUMBER` in the script's one-line JSON object (its
/// values hold no commas, braces or nested objects).
fn json_number(line: &str, key: &str) -> Option<f64> {
    let start = line.find(&format!("\"{key}\":"))? + key.len() + 3;
    let rest = &line[start..];
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].trim().parse().ok()
}

/// One point of a peer's convergence: its time and its error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    pub spp: u32,
    pub seconds: f64,
    pub rmse: f64,
}

/// The peer's renders at `start_spp`, then twice as many samples each time,
/// until one takes `budget_s` or more (or reaches `max_spp`), each with its
/// RMSE against `reference`. None when the peer is not installed.
#[allow(clippy::too_many_arguments)]
pub fn until_budget(
    runner: &Runner,
    peer: Peer,
    threads: usize,
    budget_s: f64,
    reference: &FloatImage,
    start_spp: u32,
    max_spp: u32,
    dir: &Path,
) -> Result<Option<Vec<Point>>> {
    let mut points = Vec::new();
    let mut spp = start_spp.max(1);
    loop {
        let Some(r) = run_or_retry(runner, peer, spp, threads, dir)? else {
            return Ok(None);
        };
        points.push(Point {
            spp: r.spp,
            seconds: r.seconds,
            rmse: rmse(&r.image, reference)?,
        });
        if r.seconds >= budget_s || spp >= max_spp {
            return Ok(Some(points));
        }
        spp = spp.saturating_mul(2).min(max_spp);
    }
}

/// `run`, tried a second time when it fails: Mitsuba 3.9 once died of
/// SIGBUS in a bench (not again by hand: perhaps its kernel cache in
/// ~/.drjit, shared with other processes, changing under it).
fn run_or_retry(
    runner: &Runner,
    peer: Peer,
    spp: u32,
    threads: usize,
    dir: &Path,
) -> Result<Option<Run>> {
    run(runner, peer, spp, threads, 0, dir).or_else(|first| {
        eprintln!("bench: {first:#}; once more");
        run(runner, peer, spp, threads, 0, dir)
    })
}

/// The RMSE at `budget_s`, interpolated in log-log between the renders
/// around it (extrapolated from the nearest two beyond them).
pub fn rmse_at(points: &[Point], budget_s: f64) -> Option<f64> {
    log_log(points, |p| (p.seconds, p.rmse), budget_s, -0.5)
}

/// The seconds to reach `target` RMSE, interpolated in the same way.
pub fn seconds_to(points: &[Point], target: f64) -> Option<f64> {
    log_log(points, |p| (p.rmse, p.seconds), target, -2.0)
}

/// y at x on the polyline through `points` in log-log space, ordered by x:
/// between the two points around x, or extended from the nearest two. One
/// point alone is extended with `slope` (Monte Carlo's: error ~ time^-1/2,
/// so time ~ error^-2).
fn log_log(points: &[Point], xy: impl Fn(&Point) -> (f64, f64), x: f64, slope: f64) -> Option<f64> {
    let mut pts: Vec<(f64, f64)> = points
        .iter()
        .map(xy)
        .filter(|&(x, y)| x > 0.0 && y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts.dedup_by(|a, b| a.0 == b.0);
    let lx = x.ln();
    let (a, b) = match pts.len() {
        0 => return None,
        1 => {
            let (x0, y0) = pts[0];
            return Some((y0 + slope * (lx - x0)).exp());
        }
        n => {
            let i = pts.partition_point(|p| p.0 < lx).clamp(1, n - 1);
            (pts[i - 1], pts[i])
        }
    };
    let t = (lx - a.0) / (b.0 - a.0);
    Some((a.1 + t * (b.1 - a.1)).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(rgb: Vec<f32>, width: u32) -> FloatImage {
        let height = rgb.len() as u32 / 3 / width;
        FloatImage { width, height, rgb }
    }

    #[test]
    fn rmse_is_over_every_pixel_and_channel() {
        let a = image(vec![0.0; 6], 2);
        let b = image(vec![1.0, 0.0, 0.0, 0.0, 0.0, 1.0], 2);
        assert!((rmse(&a, &b).unwrap() - (2.0f64 / 6.0).sqrt()).abs() < 1e-12);
        assert_eq!(rmse(&b, &b).unwrap(), 0.0);
        assert!(rmse(&a, &image(vec![0.0; 6], 1)).is_err());
    }

    #[test]
    fn numbers_are_read_from_the_scripts_json_line() {
        let line = r#"{"renderer": "cycles", "spp": 64, "seconds": 1.25, "cpu_s": 2.5e-1}"#;
        assert_eq!(json_number(line, "seconds"), Some(1.25));
        assert_eq!(json_number(line, "cpu_s"), Some(0.25));
        assert_eq!(json_number(line, "spp"), Some(64.0));
        assert_eq!(json_number(line, "renderer"), None);
        assert_eq!(json_number(line, "threads"), None);
    }

    /// Monte Carlo error: rmse = 0.1 / sqrt(seconds).
    fn monte_carlo(seconds: &[f64]) -> Vec<Point> {
        seconds
            .iter()
            .map(|&s| Point {
                spp: 0,
                seconds: s,
                rmse: 0.1 / s.sqrt(),
            })
            .collect()
    }

    #[test]
    fn a_power_law_is_interpolated_and_extended_exactly() {
        let points = monte_carlo(&[0.5, 1.0, 2.0, 4.0]);
        for budget in [0.25, 0.7, 3.0, 16.0] {
            let expected = 0.1 / f64::sqrt(budget);
            assert!((rmse_at(&points, budget).unwrap() - expected).abs() < 1e-12);
            // The time to reach that error is the budget again.
            assert!((seconds_to(&points, expected).unwrap() - budget).abs() < 1e-9);
        }
    }

    #[test]
    fn one_point_is_extended_with_the_monte_carlo_slope() {
        let points = monte_carlo(&[2.0]);
        assert!((rmse_at(&points, 8.0).unwrap() - 0.1 / 8f64.sqrt()).abs() < 1e-12);
        assert!((seconds_to(&points, 0.1 / 8f64.sqrt()).unwrap() - 8.0).abs() < 1e-9);
        assert_eq!(rmse_at(&[], 1.0), None);
    }

    #[test]
    fn the_bracketing_points_are_used_not_the_outer_ones() {
        // A slope change between the segments: the budget inside the first
        // one ignores the third point.
        let points = [(1.0, 0.1), (4.0, 0.05), (16.0, 0.0125)].map(|(seconds, rmse)| Point {
            spp: 0,
            seconds,
            rmse,
        });
        assert!((rmse_at(&points, 2.0).unwrap() - 0.1 / 2f64.sqrt()).abs() < 1e-12);
        assert!((rmse_at(&points, 8.0).unwrap() - 0.025).abs() < 1e-12);
    }

    #[test]
    fn the_tests_reference_reads_as_the_cornell_box() {
        // Half floats, ZIP: what the path tracer's tests compare with.
        let path = crate::workspace_root().join(CORNELL_BOX.reference);
        let r = read_image(&path).unwrap();
        assert_eq!((r.width, r.height), (256, 256));
        let mean = r.rgb.iter().map(|&x| f64::from(x)).sum::<f64>() / r.rgb.len() as f64;
        assert!((mean - 0.14708).abs() < 1e-4, "{mean}");
        // The light, near the top middle: Mitsuba's radiance plus what it reflects.
        let light = &r.rgb[(36 * 256 + 128) * 3..][..3];
        assert!((light[0] - 18.6).abs() < 0.05, "{light:?}");
    }

    /// A stand-in for the script: a shell command.
    fn sh(script: &str) -> Runner {
        Runner {
            program: "sh".into(),
            args: vec!["-c".into(), script.into(), "cornell.py".into()],
            timeout: Duration::from_secs(60),
        }
    }

    #[test]
    fn a_peer_not_installed_is_skipped_and_a_failure_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let skipped = sh("echo 'Cycles: skipped, bpy not installed' >&2; exit 3");
        assert!(run(&skipped, Peer::Cycles, 1, 1, 0, dir.path())
            .unwrap()
            .is_none());
        let failed = sh("echo 'Traceback ...' >&2; exit 1");
        let err = run(&failed, Peer::Cycles, 1, 1, 0, dir.path()).unwrap_err();
        assert!(format!("{err:#}").contains("Traceback"), "{err:#}");
    }

    #[test]
    fn a_peer_that_hangs_is_stopped() {
        let dir = tempfile::tempdir().unwrap();
        let hung = Runner {
            timeout: Duration::from_millis(200),
            ..sh("sleep 30")
        };
        let start = Instant::now();
        let err = run(&hung, Peer::Cycles, 1, 1, 0, dir.path()).unwrap_err();
        assert!(
            format!("{err:#}").contains("stopped after 0.2 s"),
            "{err:#}"
        );
        assert!(start.elapsed() < Duration::from_secs(10));
    }

    #[test]
    fn a_run_returns_its_seconds_and_image() {
        let dir = tempfile::tempdir().unwrap();
        // The stand-in copies an EXR to the path after --out (the last
        // argument) and prints its line.
        let exr = dir.path().join("source.exr");
        let pixels = image::Rgb32FImage::from_raw(2, 1, vec![0.5, 1.0, 2.0, 0.0, 0.25, 8.0]);
        pixels.unwrap().save(&exr).unwrap();
        let script = format!(
            r#"for a; do out=$a; done; cp {} "$out"; echo '{{"spp": 4, "seconds": 1.5, "cpu_s": 3}}'"#,
            exr.display()
        );
        let peer = Peer::Mitsuba {
            variant: "scalar_rgb",
            sampler: "independent",
        };
        let r = run(&sh(&script), peer, 4, 2, 0, dir.path())
            .unwrap()
            .unwrap();
        assert_eq!((r.spp, r.seconds, r.cpu_s), (4, 1.5, 3.0));
        assert_eq!(r.image, image(vec![0.5, 1.0, 2.0, 0.0, 0.25, 8.0], 2));
    }
}
