//! Timing the tracer: BVH build and render, on 1 and 2 threads, in-process.
//! The only file of the bench that calls tracer-core.

use super::process::{self, Process, Spawn};
use super::scenes::BenchScene;
use super::stats::median;
use super::THREADS;
use anyhow::Result;
use glam::Vec3;
use std::path::Path;
use std::time::Instant;
use tracer_core::accel::{Bvh, PACKET};
use tracer_core::{
    prepare, render, render_into, sample_rays, LinearImage, Output, Ray, RayStats, Region,
    RenderJob, Scene,
};

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
    let mut images: Vec<LinearImage> = prepared.iter().map(touched_image).collect();
    let mut runs = vec![Vec::new(); scenes.len()];
    let mut spawns: Vec<Vec<Spawn>> = vec![Vec::new(); scenes.len()];
    for rep in 0..reps {
        eprintln!("bench: run {} of {reps} ...", rep + 1);
        for (k, (scene, bench)) in prepared.iter().zip(scenes).enumerate() {
            let mut run = measure_run(scene, bench.samples, &pools, &mut images[k]);
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

/// Our primary rays at `samples` per pixel, on one thread, medians of
/// `reps` runs.
pub struct PrimaryRays {
    pub rays: u64,
    /// The render's distance output: nearest hits only, no shading; the
    /// rays made as the render goes, a pixel's samples searched together.
    pub render_s: f64,
    /// The same rays stored (as a peer's harness reads them), traced 16 at
    /// a time, a pixel's samples (`Scene::closest_hits`).
    pub stored_s: f64,
    /// How many of the stored rays hit.
    pub hits: u64,
}

/// Measures `PrimaryRays` on `file`. The rays are first written to
/// `rays_file` for a peer: a u32 count, the common origin, then each
/// direction (f32, little-endian).
pub fn primary_rays(
    file: &scene_format::SceneFile,
    samples: u32,
    reps: usize,
    rays_file: &Path,
) -> Result<PrimaryRays> {
    let scene = prepare(file).map_err(|e| anyhow::anyhow!("{e}"))?;
    let camera = scene.camera();
    let job = RenderJob {
        region: Region::full(camera.width, camera.height),
        samples,
        output: Output::Distance,
    };
    let (origin, dirs) = write_rays(&scene, &job, rays_file)?;
    let pool = pool(1)?;
    let timed = |work: &mut (dyn FnMut() + Send)| {
        let start = Instant::now();
        pool.install(&mut *work);
        start.elapsed().as_secs_f64()
    };
    let mut hits = 0;
    let (mut render_s, mut stored_s) = (Vec::new(), Vec::new());
    for _ in 0..reps {
        render_s.push(timed(&mut || drop(render(&scene, &job, &|_| {}))));
        stored_s.push(timed(&mut || hits = trace_stored(&scene, origin, &dirs)));
    }
    Ok(PrimaryRays {
        rays: dirs.len() as u64,
        render_s: median(render_s),
        stored_s: median(stored_s),
        hits,
    })
}

/// Traces rays from `origin` along `dirs`, 16 at a time; how many hit.
fn trace_stored(scene: &Scene, origin: Vec3, dirs: &[Vec3]) -> u64 {
    let (mut rays, mut hits) = ([Ray::new(origin, origin); PACKET], [None; PACKET]);
    let mut found = 0;
    for chunk in dirs.chunks(PACKET) {
        for (ray, &dir) in rays.iter_mut().zip(chunk) {
            *ray = Ray::new(origin, dir);
        }
        let (rays, hits) = (&rays[..chunk.len()], &mut hits[..chunk.len()]);
        scene.closest_hits(rays, tracer_core::EPSILON, f32::INFINITY, hits);
        found += hits.iter().filter(|h| h.is_some()).count() as u64;
    }
    found
}

/// Writes the primary rays of `job` to `path` (see `primary_rays`);
/// returns their origin and directions.
fn write_rays(scene: &Scene, job: &RenderJob, path: &Path) -> Result<(Vec3, Vec<Vec3>)> {
    use std::io::Write;
    let (mut origin, mut dirs) = (None, Vec::new());
    let mut several = false;
    sample_rays(scene, job, |ray| {
        several |= *origin.get_or_insert(ray.origin()) != ray.origin();
        dirs.push(ray.dir());
    });
    if several {
        anyhow::bail!("rays from several origins");
    }
    let origin = origin.unwrap_or_default();
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    out.write_all(&u32::try_from(dirs.len())?.to_le_bytes())?;
    for v in std::iter::once(&origin).chain(&dirs) {
        out.write_all(&v.to_array().map(f32::to_le_bytes).concat())?;
    }
    out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok((origin, dirs))
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

/// An image of `scene`'s size whose pages are mapped: each render is timed
/// into it (`render_into`), as Embree's harness renders into a frame it
/// allocated and filled before its timing. A fresh image's first touch
/// cost the bunny's render a tenth of its time, and two threads more
/// (they fault in the same address space), a cost a `tracer render`
/// process pays once.
fn touched_image(scene: &Scene) -> LinearImage {
    let camera = scene.camera();
    let mut image = LinearImage::new(camera.width, camera.height);
    // Written (with a value the compiler cannot know is zero), not only
    // allocated: the allocator hands out zero pages unmapped.
    image.pixels.fill(std::hint::black_box(Vec3::ZERO));
    image
}

fn measure_run(
    scene: &Scene,
    samples: u32,
    pools: &[rayon::ThreadPool; 2],
    image: &mut LinearImage,
) -> Run {
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
        let never = std::sync::atomic::AtomicBool::new(false);
        let (start, cpu) = (Instant::now(), cpu_time());
        let rays = pool.install(|| render_into(scene, &job, &|_| {}, &never, image));
        run.render_s[t] = start.elapsed().as_secs_f64();
        let render_cpu = cpu_time() - cpu;
        let rays = rays.expect("never cancelled");
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
