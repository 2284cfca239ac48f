//! Timing the tracer: BVH build and render, on 1 and 2 threads, in-process.
//! The only file of the bench that calls tracer-core.

use super::process::{self, Process, Spawn};
use super::scenes::BenchScene;
use super::stats::median;
use super::THREADS;
use anyhow::Result;
use std::path::Path;
use std::time::Instant;
use tracer_core::accel::Bvh;
use tracer_core::{prepare, render, sample_rays, Output, RayStats, Region, RenderJob, Scene};

/// The rays one render traced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Rays {
    /// Primary (every sample's) and reflected rays: they look for the nearest
    /// hit.
    pub nearest: u64,
    /// Shadow rays.
    pub shadow: u64,
}

impl Rays {
    pub fn total(&self) -> u64 {
        self.nearest + self.shadow
    }
}

impl From<RayStats> for Rays {
    fn from(r: RayStats) -> Rays {
        Rays {
            nearest: r.nearest,
            shadow: r.shadow,
        }
    }
}

/// The tracer's figures on one scene: medians over the runs.
#[derive(Debug, Default)]
pub struct Ours {
    /// Objects of the prepared scene (every mesh triangle is one).
    pub objects: usize,
    /// Pixels of the image: rays per pixel are taken over them.
    pub pixels: u64,
    pub build_s: [f64; 2],
    pub render_s: [f64; 2],
    /// Reading its mesh's OBJ file (on one thread), when the scene has one.
    pub load_s: Option<f64>,
    /// The tree's cost by the surface area heuristic (the same every run).
    pub sah_cost: f64,
    /// Process CPU time of the 1-thread build and render: what the work
    /// costs when other processes take turns on the cores.
    pub build_cpu_s: f64,
    pub render_cpu_s: f64,
    pub rays: Rays,
    /// Each run's 1-thread / 2-thread render time, in run order.
    pub speedup_runs: Vec<f64>,
    /// Each run's 1-thread CPU nanoseconds per ray, in run order.
    pub ns_per_ray_runs: Vec<f64>,
    /// The whole `tracer render` process on one thread, when timed.
    pub process: Option<Process>,
}

impl Ours {
    /// Mrays/s of the render on `THREADS[t]` threads, wall time.
    pub fn mrays(&self, t: usize) -> f64 {
        self.rays.total() as f64 / self.render_s[t] / 1e6
    }
    /// Mrays per CPU-second on one thread.
    pub fn mrays_per_cpu_s(&self) -> f64 {
        self.rays.total() as f64 / self.render_cpu_s / 1e6
    }
    /// On one thread, from CPU time.
    pub fn ns_per_ray(&self) -> f64 {
        self.render_cpu_s * 1e9 / self.rays.total() as f64
    }
}

/// One run of one scene: build and render on 1 thread, then on 2.
#[derive(Debug, Clone, Copy, Default)]
struct Run {
    load_s: Option<f64>,
    sah_cost: f64,
    build_s: [f64; 2],
    render_s: [f64; 2],
    build_cpu_s: f64,
    render_cpu_s: f64,
    rays: Rays,
}

/// Runs every scene `reps` times, taking turns: run r of each scene and its
/// 1- and 2-thread halves are measured close together in time, so the
/// ratios between them (speed-up, cost at 1.1M / at 70k) are taken within a
/// run, where the machine's slow swings in speed cancel out. A scene with a
/// `process` file is also rendered by `tracer` (its binary), writing into
/// `out_dir`, a few times a run.
pub fn measure(
    scenes: &[BenchScene],
    reps: usize,
    tracer: Option<&Path>,
    out_dir: &Path,
) -> Result<Vec<Ours>> {
    let prepared = scenes
        .iter()
        .map(|s| prepare(&s.file).map_err(|e| anyhow::anyhow!("{e}")))
        .collect::<Result<Vec<_>>>()?;
    let pools = [pool(THREADS[0])?, pool(THREADS[1])?];
    let mut runs = vec![Vec::new(); scenes.len()];
    let mut spawns: Vec<Vec<Spawn>> = vec![Vec::new(); scenes.len()];
    for rep in 0..reps {
        eprintln!("bench: run {} of {reps} ...", rep + 1);
        for (k, (scene, bench)) in prepared.iter().zip(scenes).enumerate() {
            let mut run = measure_run(scene, bench.samples, &pools);
            run.load_s = bench.obj.as_deref().map(time_obj_read).transpose()?;
            runs[k].push(run);
            if let (Some(file), Some(tracer)) = (&bench.process, tracer) {
                let out = out_dir.join(format!("{}.png", bench.name));
                for _ in 0..process::SPAWNS_PER_RUN {
                    spawns[k].push(process::spawn(tracer, file, &out)?);
                }
            }
        }
    }
    Ok(prepared
        .iter()
        .zip(runs)
        .zip(spawns)
        .map(|((p, runs), spawns)| {
            let camera = p.camera();
            let pixels = u64::from(camera.width) * u64::from(camera.height);
            Ours {
                process: (!spawns.is_empty()).then(|| Process::of(&spawns)),
                ..summarise(p.objects().len(), pixels, &runs)
            }
        })
        .collect())
}

/// Our primary rays at `samples` per pixel on one thread: the distance
/// output (nearest hits only, no shading; a pixel's samples searched
/// together), the median seconds of `reps` renders; and how many rays. The
/// same rays are first written to `rays_file` for a peer: a u32 count, the
/// common origin, then each direction (f32, little-endian).
pub fn primary_rays(
    file: &scene_format::SceneFile,
    samples: u32,
    reps: usize,
    rays_file: &Path,
) -> Result<(u64, f64)> {
    let scene = prepare(file).map_err(|e| anyhow::anyhow!("{e}"))?;
    let camera = scene.camera();
    let job = RenderJob {
        region: Region::full(camera.width, camera.height),
        samples,
        output: Output::Distance,
    };
    let rays = write_rays(&scene, &job, rays_file)?;
    let pool = pool(1)?;
    let times = (0..reps)
        .map(|_| {
            let start = Instant::now();
            let image = pool.install(|| render(&scene, &job, &|_| {}).image);
            let seconds = start.elapsed().as_secs_f64();
            drop(image);
            seconds
        })
        .collect();
    Ok((rays, median(times)))
}

/// Writes the primary rays of `job` to `path` (see `primary_rays`);
/// returns how many.
fn write_rays(scene: &Scene, job: &RenderJob, path: &Path) -> Result<u64> {
    use std::io::{Seek, SeekFrom, Write};
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    out.write_all(&[0; 16])?;
    let (mut count, mut origin, mut failed) = (0u32, None, None);
    sample_rays(scene, job, |ray| {
        if *origin.get_or_insert(ray.origin) != ray.origin {
            failed.get_or_insert_with(|| anyhow::anyhow!("rays from several origins"));
        }
        let bytes = ray.dir.to_array().map(f32::to_le_bytes).concat();
        if let Err(e) = out.write_all(&bytes) {
            failed.get_or_insert(e.into());
        }
        count += 1;
    });
    if let Some(e) = failed {
        return Err(e);
    }
    let mut out = out.into_inner().map_err(|e| e.into_error())?;
    out.seek(SeekFrom::Start(0))?;
    out.write_all(&count.to_le_bytes())?;
    let origin = origin.unwrap_or_default().to_array().map(f32::to_le_bytes);
    out.write_all(&origin.concat())?;
    out.sync_all()?;
    Ok(u64::from(count))
}

/// Seconds to read the OBJ file at `path` into triangles.
fn time_obj_read(path: &std::path::Path) -> Result<f64> {
    let start = Instant::now();
    let data = scene_format::obj::read_obj(path).map_err(|e| anyhow::anyhow!("{e}"))?;
    let seconds = start.elapsed().as_secs_f64();
    drop(data);
    Ok(seconds)
}

fn pool(threads: usize) -> Result<rayon::ThreadPool> {
    Ok(rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?)
}

fn measure_run(scene: &Scene, samples: u32, pools: &[rayon::ThreadPool; 2]) -> Run {
    // Spelt out rather than `RenderJob::full`, so that the bench keeps its
    // sample counts whatever that default becomes.
    let camera = scene.camera();
    let job = RenderJob {
        region: Region::full(camera.width, camera.height),
        samples,
        output: Output::Shading,
    };
    let mut run = Run::default();
    for (t, pool) in pools.iter().enumerate() {
        let (start, cpu) = (Instant::now(), cpu_time());
        let bvh = pool.install(|| Bvh::build(scene.objects()));
        run.build_s[t] = start.elapsed().as_secs_f64();
        let build_cpu = cpu_time() - cpu;
        run.sah_cost = bvh.sah_cost();
        drop(bvh);
        let (start, cpu) = (Instant::now(), cpu_time());
        let rendered = pool.install(|| render(scene, &job, &|_| {}));
        let (image, rays) = (rendered.image, rendered.rays);
        run.render_s[t] = start.elapsed().as_secs_f64();
        let render_cpu = cpu_time() - cpu;
        drop(image);
        if t == 0 {
            (run.build_cpu_s, run.render_cpu_s) = (build_cpu, render_cpu);
        }
        run.rays = rays.into();
    }
    run
}

/// Medians of the runs, and each run's own speed-up and cost per ray.
fn summarise(objects: usize, pixels: u64, runs: &[Run]) -> Ours {
    let med = |f: &dyn Fn(&Run) -> f64| median(runs.iter().map(f).collect());
    let rays = runs[0].rays;
    Ours {
        objects,
        pixels,
        build_s: [med(&|r| r.build_s[0]), med(&|r| r.build_s[1])],
        load_s: runs[0]
            .load_s
            .map(|_| med(&|r| r.load_s.unwrap_or(f64::NAN))),
        sah_cost: runs[0].sah_cost,
        render_s: [med(&|r| r.render_s[0]), med(&|r| r.render_s[1])],
        build_cpu_s: med(&|r| r.build_cpu_s),
        render_cpu_s: med(&|r| r.render_cpu_s),
        rays,
        speedup_runs: runs.iter().map(|r| r.render_s[0] / r.render_s[1]).collect(),
        ns_per_ray_runs: runs
            .iter()
            .map(|r| r.render_cpu_s * 1e9 / rays.total() as f64)
            .collect(),
        process: None,
    }
}

/// CPU seconds this process has used, on all its threads.
fn cpu_time() -> f64 {
    super::rusage::cpu_seconds(&super::rusage::of(libc::RUSAGE_SELF))
}
