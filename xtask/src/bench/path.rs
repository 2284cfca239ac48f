//! `cargo xtask bench --only path`: the path tracer against Mitsuba 3 at
//! equal time, on 1 and 2 threads, on four scenes: Mitsuba's Cornell box
//! (`scenes/cornell-box.toml`), metal and glass under a studio's light
//! (`scenes/materials.toml`), the 70k-triangle bunny and rough gold in the
//! Cornell box (`scenes/cornell-bunny.toml`) and textures under an HDR sky
//! (`scenes/courtyard.toml`). Each renderer renders at doubling samples
//! per pixel until a render takes the time budget; its RMSE against the
//! same high-sample reference (Mitsuba's, the scene's `reference`) at the
//! budget, and the time it takes to reach the scene's target RMSE, are read
//! off its error curve in log-log. The summary is issue 53's table: ours
//! over the better of Mitsuba's two samplers at equal time (the ratio of
//! RMSE x sqrt(seconds)). The peers run through the scene's script in
//! `xtask/peers/` (`path_peers`); one that is not installed is skipped with
//! one line.

use super::path_peers::{self, BenchScene, FloatImage, Peer, Point, Runner};
use super::rusage;
use super::THREADS;
use anyhow::{Context, Result};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tracer_core::scene::TraceSettings;
use tracer_core::{Region, RenderJob, Scene};

/// The `--only` name of this measurement.
pub const PATH: &str = "path";

/// The time budget of a renderer's curve on each thread count of
/// `THREADS`: about Mitsuba's time for 256 samples per pixel.
const BUDGET_S: [f64; 2] = [8.0, 4.0];

/// The samples per pixel our curve starts at, and its largest.
const OUR_SPP: (u32, u32) = (16, 4096);
/// The peers' (below 64 their start-up dominates, and their times are noise).
const PEER_SPP: (u32, u32) = (64, 4096);

/// One renderer's curve on one thread count.
#[derive(Debug, Clone)]
pub struct Curve {
    pub scene: &'static str,
    pub renderer: String,
    /// The peer that rendered it; None for ours.
    pub peer: Option<Peer>,
    pub threads: usize,
    pub points: Vec<Point>,
    /// CPU seconds over wall seconds of its last render, against the
    /// thread count: below it, the machine was busy with something else.
    pub cpu_share: f64,
    /// The image's pixels.
    pub pixels: f64,
}

impl Curve {
    pub fn rmse_at_budget(&self) -> Option<f64> {
        path_peers::rmse_at(&self.points, BUDGET_S[thread_slot(self.threads)])
    }

    /// The seconds to reach `target` RMSE.
    pub fn seconds_to(&self, target: f64) -> Option<f64> {
        path_peers::seconds_to(&self.points, target)
    }

    /// Paths per second, in millions, of its render nearest the budget in
    /// time: a peer's speed may change with the samples (Mitsuba's
    /// `multijitter` ran 2.1 M paths/s at 256 and 1.5 M at 528 on the
    /// Cornell box), and the one that counts is the speed at the budget.
    fn mpaths(&self) -> f64 {
        let budget = BUDGET_S[thread_slot(self.threads)];
        let off = |p: &Point| (p.seconds / budget).ln().abs();
        let nearest = self
            .points
            .iter()
            .min_by(|a, b| off(a).total_cmp(&off(b)))
            .expect("a curve has points");
        self.pixels * f64::from(nearest.spp) / nearest.seconds / 1e6
    }
}

fn thread_slot(threads: usize) -> usize {
    THREADS.iter().position(|&t| t == threads).unwrap_or(0)
}

/// The scenes measured, in the report's order.
const SCENES: [BenchScene; 4] = [
    path_peers::CORNELL_BOX,
    path_peers::MATERIALS,
    path_peers::CORNELL_BUNNY,
    path_peers::COURTYARD,
];

/// Our curves and every installed peer's, on each scene and thread count:
/// `Peer::MITSUBA`'s, and with `all_peers` each scene's `more_peers`.
pub fn measure(root: &Path, dir: &Path, all_peers: bool) -> Result<Vec<Curve>> {
    let mut curves = Vec::new();
    let peers_of = |bench: &BenchScene| {
        let more = if all_peers { bench.more_peers } else { &[] };
        Peer::MITSUBA
            .iter()
            .chain(more)
            .copied()
            .collect::<Vec<_>>()
    };
    let every_peer: Vec<Peer> = SCENES.iter().flat_map(peers_of).collect();
    path_peers::install_missing(&every_peer);
    for bench in SCENES {
        curves.extend(measure_scene(root, dir, bench, &peers_of(&bench))?);
    }
    Ok(curves)
}

fn measure_scene(root: &Path, dir: &Path, bench: BenchScene, peers: &[Peer]) -> Result<Vec<Curve>> {
    let reference = path_peers::read_image(&root.join(bench.reference))?;
    let scene = load(&root.join(bench.scene))?;
    let shared = with_settings(scene.clone(), |s| (s.path_reuse, s.camera_rays) = SHARED);
    let adaptive = with_settings(scene.clone(), |s| s.adaptive = true);
    let runner = Runner::new(root, bench.script);
    let pixels = f64::from(reference.width) * f64::from(reference.height);
    let mut curves = Vec::new();
    for (slot, &threads) in THREADS.iter().enumerate() {
        eprintln!(
            "bench: path tracing {} on {threads} thread(s) ...",
            bench.scene
        );
        let ours_curves = [
            (OURS, &scene),
            (OURS_SHARED, &shared),
            (OURS_ADAPTIVE, &adaptive),
        ];
        for (renderer, scene) in ours_curves {
            let work = (bench.scene, renderer);
            curves.push(ours(work, scene, threads, BUDGET_S[slot], &reference)?);
        }
        for &peer in peers {
            eprintln!("bench: {} on {threads} thread(s) ...", peer.name());
            let (start, max) = PEER_SPP;
            let points = path_peers::until_budget(
                &runner,
                peer,
                threads,
                BUDGET_S[slot],
                &reference,
                start,
                max,
                dir,
            );
            // A peer failing twice leaves its curve out, not the run's others.
            let points = points.unwrap_or_else(|e| {
                eprintln!("bench: {e:#}; its curve is left out");
                None
            });
            if let Some(points) = points {
                curves.push(Curve {
                    scene: bench.scene,
                    renderer: peer.name(),
                    peer: Some(peer),
                    threads,
                    points,
                    cpu_share: f64::NAN,
                    pixels,
                });
            }
        }
    }
    Ok(curves)
}

/// Our second curve's `render.path_reuse` (the pixels of a group that
/// share their paths' first bounces) and `render.camera_rays` (camera
/// rays per path where a pixel shows a light's edge); the scenes' files
/// leave both at 1.
const SHARED: (u32, u32) = (8, 8);

/// The name of our curve with the scene's own settings.
const OURS: &str = "tracer (ours)";

/// The name of that curve.
const OURS_SHARED: &str = "ours, path_reuse 8, camera_rays 8";

/// The name of our curve with adaptive sampling (`render.adaptive`).
const OURS_ADAPTIVE: &str = "ours, adaptive";

/// `scene` with its trace settings as `change` leaves them.
fn with_settings(scene: Scene, change: impl FnOnce(&mut TraceSettings)) -> Scene {
    let mut settings = scene.trace_settings().clone();
    change(&mut settings);
    scene.with_trace_settings(settings)
}

/// The scene, prepared as `tracer render` prepares it.
fn load(path: &Path) -> Result<Scene> {
    let file = scene_format::load_path(path).with_context(|| path.display().to_string())?;
    Ok(tracer_core::prepare(&file)?)
}

/// Our renders at doubling samples per pixel on `threads` threads, until
/// one takes `budget_s`: the render alone is timed (the scene is prepared
/// once, as a peer's load and compilation are left out of its time).
fn ours(
    (name, renderer): (&'static str, &str),
    scene: &Scene,
    threads: usize,
    budget_s: f64,
    reference: &FloatImage,
) -> Result<Curve> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let (mut spp, max) = OUR_SPP;
    let mut points = Vec::new();
    let mut cpu_share;
    let never = AtomicBool::new(false);
    loop {
        let camera = scene.camera();
        let job = RenderJob::full(scene).with_samples(spp);
        let job = RenderJob {
            region: Region::full(camera.width, camera.height),
            ..job
        };
        let cpu = rusage::cpu_seconds(&rusage::of(libc::RUSAGE_SELF));
        let start = Instant::now();
        let rendered = pool
            .install(|| tracer_core::render_cancellable(scene, &job, &|_| {}, &never))
            .context("a render that is never cancelled")?;
        let seconds = start.elapsed().as_secs_f64();
        cpu_share = (rusage::cpu_seconds(&rusage::of(libc::RUSAGE_SELF)) - cpu) / seconds;
        let image = FloatImage {
            width: rendered.image.width,
            height: rendered.image.height,
            rgb: rendered
                .image
                .pixels
                .iter()
                .flat_map(|c| c.to_array())
                .collect(),
        };
        points.push(Point {
            spp,
            seconds,
            rmse: path_peers::rmse(&image, reference)?,
        });
        if seconds >= budget_s || spp >= max {
            break;
        }
        spp *= 2;
    }
    let camera = scene.camera();
    Ok(Curve {
        scene: name,
        renderer: renderer.into(),
        peer: None,
        threads,
        points,
        cpu_share,
        pixels: f64::from(camera.width) * f64::from(camera.height),
    })
}

/// The table of every curve, and ours against the best peer at equal time,
/// scene by scene; then issue 53's table of the equal-time error ratios.
pub fn report(curves: &[Curve]) {
    for bench in SCENES {
        let mine: Vec<Curve> = curves
            .iter()
            .filter(|c| c.scene == bench.scene)
            .cloned()
            .collect();
        report_scene(&bench, &mine);
    }
    summary(curves);
}

fn report_scene(bench: &BenchScene, curves: &[Curve]) {
    println!();
    println!("Path tracing: {}, box filter;", bench.title);
    println!(
        "RMSE against Mitsuba's high-sample reference (its own noise {}), at equal time.",
        bench.reference_noise
    );
    for &threads in &THREADS {
        let slot = thread_slot(threads);
        let mine: Vec<&Curve> = curves.iter().filter(|c| c.threads == threads).collect();
        println!();
        println!("{threads} thread(s), budget {:.0} s:", BUDGET_S[slot]);
        println!(
            "  {:<36} {:>10} {:>18} {:>13} {:>15} {:>14}",
            "renderer",
            "last spp",
            "Mpaths/s at budget",
            "RMSE at 256",
            "RMSE at budget",
            format!("s to RMSE {}", bench.target_rmse)
        );
        for c in &mine {
            let at_256 = rmse_at_samples(&c.points, 256);
            println!(
                "  {:<36} {:>10} {:>18.2} {:>13} {:>15} {:>14}",
                c.renderer,
                c.points.last().map_or(0, |p| p.spp),
                c.mpaths(),
                show(at_256, 4),
                show(c.rmse_at_budget(), 4),
                show(c.seconds_to(bench.target_rmse), 2),
            );
        }
        for ours in mine.iter().filter(|c| c.peer.is_none()) {
            if let Some((ratio, best)) = equal_time_ratio(ours, &mine) {
                println!(
                    "  {} / best Mitsuba sampler ({}) at equal time: {ratio:.2} (goal: at most 0.50)",
                    ours.renderer, best.renderer,
                );
            }
            if ours.cpu_share < 0.9 * threads as f64 {
                println!(
                    "  (our renders had {:.2} CPU-seconds a second for {threads} thread(s): the machine was busy)",
                    ours.cpu_share
                );
            }
        }
    }
}

/// `ours` over the better of `Peer::MITSUBA`'s curves among `curves` (on
/// its scene and thread count) at equal time: the ratio of their RMSE at
/// the budget, which is that of their RMSE x sqrt(seconds) wherever the
/// error falls as the root of the time. With that curve.
fn equal_time_ratio<'a>(ours: &Curve, curves: &[&'a Curve]) -> Option<(f64, &'a Curve)> {
    let (best, best_rmse) = best_mitsuba(ours.scene, ours.threads, curves)?;
    Some((ours.rmse_at_budget()? / best_rmse, best))
}

/// The curve of `Peer::MITSUBA` with the least RMSE at the budget on
/// `scene` and `threads`, and that RMSE.
fn best_mitsuba<'a>(scene: &str, threads: usize, curves: &[&'a Curve]) -> Option<(&'a Curve, f64)> {
    curves
        .iter()
        .filter(|c| c.scene == scene && c.threads == threads)
        .filter(|c| c.peer.is_some_and(|p| Peer::MITSUBA.contains(&p)))
        .filter_map(|c| Some((*c, c.rmse_at_budget()?)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Issue 53's table: each scene and thread count, ours with the scene's
/// settings and with `SHARED`'s over the better Mitsuba sampler at equal
/// time.
fn summary(curves: &[Curve]) {
    let all: Vec<&Curve> = curves.iter().collect();
    println!();
    println!(
        "Equal-time error ratio: our RMSE x sqrt(seconds) over the better of Mitsuba 3 \
         llvm_ad_rgb's independent and multijitter samplers' (below 1: ahead of Mitsuba; \
         goal: at most 0.5)."
    );
    println!();
    println!(
        "| scene | threads | Mitsuba's better sampler, RMSE x sqrt(s) | scene defaults | `path_reuse = {}`, `camera_rays = {}` | `adaptive = true` |",
        SHARED.0, SHARED.1
    );
    println!("| --- | ---: | --- | ---: | ---: | ---: |");
    for bench in SCENES {
        for &threads in &THREADS {
            let best = best_mitsuba(bench.scene, threads, &all).map_or("-".into(), |(c, rmse)| {
                let sampler = c.renderer.rsplit(' ').next().unwrap_or("");
                format!(
                    "{sampler}, {:.4}",
                    rmse * BUDGET_S[thread_slot(threads)].sqrt()
                )
            });
            let ratio = |renderer: &str| {
                let ours = all.iter().find(|c| {
                    c.scene == bench.scene && c.threads == threads && c.renderer == renderer
                });
                show(ours.and_then(|c| equal_time_ratio(c, &all)).map(|r| r.0), 2)
            };
            println!(
                "| `{}` | {threads} | {best} | {} | {} | {} |",
                bench.scene,
                ratio(OURS),
                ratio(OURS_SHARED),
                ratio(OURS_ADAPTIVE)
            );
        }
    }
}

/// The RMSE at `spp` samples per pixel, read off the curve as
/// `path_peers::rmse_at` reads it at a time.
fn rmse_at_samples(points: &[Point], spp: u32) -> Option<f64> {
    let by_samples: Vec<Point> = points
        .iter()
        .map(|p| Point {
            seconds: f64::from(p.spp),
            ..*p
        })
        .collect();
    path_peers::rmse_at(&by_samples, f64::from(spp))
}

fn show(value: Option<f64>, decimals: usize) -> String {
    value.map_or("-".into(), |v| format!("{v:.decimals$}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_speed_reported_is_the_renders_nearest_the_budget() {
        // 1 pixel; 256 paths in 8 s (the budget on 1 thread), then a slower
        // 512 in 32 s: the speed at the budget is 32 paths/s, not 16.
        let point = |spp, seconds| Point {
            spp,
            seconds,
            rmse: 0.01,
        };
        let curve = Curve {
            scene: "s",
            renderer: "r".into(),
            peer: None,
            threads: THREADS[0],
            points: vec![point(64, 2.5), point(256, 8.0), point(512, 32.0)],
            cpu_share: 1.0,
            pixels: 1.0,
        };
        let budget = BUDGET_S[thread_slot(curve.threads)];
        assert_eq!(budget, 8.0, "the budget this test assumes");
        assert!(
            (curve.mpaths() - 32.0 / 1e6).abs() < 1e-12,
            "{}",
            curve.mpaths()
        );
    }

    #[test]
    fn the_ratio_is_against_the_better_of_mitsuba_s_two_samplers_only() {
        // Each curve one render at the budget: its RMSE there is the point's.
        let budget = BUDGET_S[thread_slot(THREADS[0])];
        let curve = |peer: Option<Peer>, rmse| Curve {
            scene: "s",
            renderer: peer.map_or(OURS.into(), |p| p.name()),
            peer,
            threads: THREADS[0],
            points: vec![Point {
                spp: 256,
                seconds: budget,
                rmse,
            }],
            cpu_share: 1.0,
            pixels: 1.0,
        };
        let [independent, multijitter] = Peer::MITSUBA;
        let ours = curve(None, 0.006);
        let curves = [
            curve(Some(independent), 0.02),
            curve(Some(multijitter), 0.012),
            // Faster than both, but not one of the two the issue compares with.
            curve(Some(Peer::SCALAR), 0.003),
            curve(Some(Peer::Cycles), 0.001),
        ];
        let all: Vec<&Curve> = curves.iter().collect();
        let (ratio, best) = equal_time_ratio(&ours, &all).unwrap();
        assert!((ratio - 0.5).abs() < 1e-12, "{ratio}");
        assert_eq!(best.peer, Some(multijitter));
    }
}
