//! `cargo xtask bench --only web`: the playground's speed. The same scenes
//! rendered natively on one thread and in headless Chromium on one worker
//! (both: load the scene, prepare it, render it whole, as crates/web does),
//! their ratio; and the page's speed-up with a worker per core.

use super::stats::median;
use anyhow::{Context, Result};
use headless::Browser;
use std::path::Path;
use std::time::{Duration, Instant};
use tracer_pipeline::{Input, Options};

/// The `--only` name of this measurement.
pub const WEB: &str = "web";

/// The scenes measured, paths under scenes/.
const SCENES: [&str; 2] = ["reflectance2.toml", "bench/bunny.toml"];

/// One scene's figures, seconds (medians).
#[derive(Debug)]
pub struct Figures {
    pub scene: &'static str,
    pub native: f64,
    /// One worker: the wasm's own time for the render.
    pub wasm: f64,
    /// The page's full render (wall time) on one worker, and on `workers`.
    pub page_one: f64,
    pub page_many: f64,
    pub workers: usize,
}

/// Measures every scene, `reps` runs each; None (with a notice) when
/// Chromium or the wasm toolchain is missing.
pub fn measure(root: &Path, reps: usize) -> Result<Option<Vec<Figures>>> {
    let Some(chromium) = headless::find_chromium() else {
        eprintln!("bench: skipping web: no Chromium (Debian: apt-get install chromium)");
        return Ok(None);
    };
    if let Err(e) = crate::web::toolchain::find() {
        eprintln!("bench: skipping web: {e:#}");
        return Ok(None);
    }
    eprintln!("bench: building the playground ...");
    let out = crate::target_dir().join("web-bench");
    crate::web::build(root, &out)?;
    let addr = crate::web::serve::start(&out, "127.0.0.1:0")?;
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut figures = Vec::new();
    for scene in SCENES {
        eprintln!("bench: {scene} natively on 1 thread ...");
        let native = median(
            (0..reps)
                .map(|_| native_seconds(&root.join("scenes").join(scene)))
                .collect::<Result<Vec<_>>>()?,
        );
        eprintln!("bench: {scene} in Chromium on 1 and {workers} workers ...");
        let one = page_runs(&chromium, &format!("http://{addr}/?workers=1"), scene, reps)?;
        let many = page_runs(
            &chromium,
            &format!("http://{addr}/?workers={workers}"),
            scene,
            reps,
        )?;
        figures.push(Figures {
            scene,
            native,
            wasm: median(one.iter().map(|r| r.0).collect()),
            page_one: median(one.iter().map(|r| r.1).collect()),
            page_many: median(many.iter().map(|r| r.1).collect()),
            workers,
        });
    }
    Ok(Some(figures))
}

/// Load and render on one thread, as one worker does.
fn native_seconds(scene: &Path) -> Result<f64> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    pool.install(|| {
        let start = Instant::now();
        let loaded = tracer_pipeline::load(&Input::File(scene.to_path_buf()))?;
        tracer_pipeline::render(&loaded, &Options::default(), &|_| {})?;
        Ok(start.elapsed().as_secs_f64())
    })
}

/// `reps` full renders of `scene` in the page at `url`: each the slowest
/// worker's own time and the page's wall time, seconds.
fn page_runs(chromium: &Path, url: &str, scene: &str, reps: usize) -> Result<Vec<(f64, f64)>> {
    let mut page = Browser::open(chromium, url)?;
    let limit = Duration::from_secs(600);
    let done = "document.getElementById('image').dataset.state === 'done'";
    page.wait_for(done, limit)?;
    page.eval(&format!(
        "(() => {{ const m = document.getElementById('scene-menu'); \
         m.value = {}; m.dispatchEvent(new Event('change')); }})()",
        serde_json::to_string(scene)?
    ))?;
    let mut runs = Vec::new();
    for rep in 0..reps {
        if rep > 0 {
            // An edit renders again (a comment: the same image).
            page.eval(&format!(
                "tracerPage.view.dispatch({{changes: {{from: tracerPage.view.state.doc.length, insert: '# {rep}\\n'}}}})"
            ))?;
        }
        page.wait_for(
            &format!(
                "document.getElementById('image').dataset.state === 'done' && \
                 tracerPage.lastRender.scene === {} && tracerPage.renders > {}",
                serde_json::to_string(scene)?,
                rep + 1
            ),
            limit,
        )?;
        let last = page.eval("tracerPage.lastRender")?;
        let worker = last["workerSeconds"].as_f64().context("no workerSeconds")?;
        let wall = last["seconds"].as_f64().context("no seconds")?;
        runs.push((worker, wall));
    }
    Ok(runs)
}

pub fn report(figures: &[Figures]) {
    println!();
    println!("The playground (headless Chromium) against the native tracer:");
    println!(
        "{:<20} {:>12} {:>12} {:>7} {:>13} {:>13} {:>9}",
        "scene", "native 1 thr", "wasm 1 wkr", "ratio", "page 1 wkr", "page N wkr", "speed-up"
    );
    for f in figures {
        println!(
            "{:<20} {:>10.3} s {:>10.3} s {:>6.2}x {:>11.3} s {:>8.3} s ({}) {:>8.2}x",
            f.scene,
            f.native,
            f.wasm,
            f.wasm / f.native,
            f.page_one,
            f.page_many,
            f.workers,
            f.page_one / f.page_many
        );
    }
    println!(
        "(native and wasm 1 wkr: load, prepare and render, whole image; page: the full \
         render as the page times it, with N workers each rendering a band)"
    );
}
