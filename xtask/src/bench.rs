//! `cargo xtask bench`: the tracer against its peers on the benchmark scenes
//! of `../shared/bench/README.md`, all in one run (the machines are noisy:
//! only figures of the same run compare).
//!
//! For each scene (the bunny, its 1.1M-triangle variant, the lab's
//! reflectance2): BVH build time, render time and Mrays/s (primary +
//! shadow + reflected) on 1 and 2 threads, medians of `--reps` runs; and
//! POV-Ray 3.7's render-only time ("Trace Time") for the same scene when
//! `povray` is installed.

use anyhow::{bail, Context, Result};
use scene_format::{MeshData, SceneFile};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;
use tracer_core::accel::Bvh;
use tracer_core::{prepare, render, RayStats, RenderJob, Scene};

/// Options of `cargo xtask bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchArgs {
    /// Runs of each measurement; the median is reported
    #[arg(long, default_value_t = 5)]
    pub reps: usize,
    /// The peers' folder (POV-Ray scene writer, reflectance2.pov)
    #[arg(long, value_name = "DIR")]
    pub peers: Option<PathBuf>,
    /// Skip POV-Ray even when it is installed
    #[arg(long)]
    pub no_povray: bool,
    /// Skip Embree even when it can be built (libembree-dev and g++)
    #[arg(long)]
    pub no_embree: bool,
    /// Only these scenes (bunny, bunny-1.1m, reflectance2)
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
}

const THREADS: [usize; 2] = [1, 2];

struct BenchScene {
    name: &'static str,
    file: SceneFile,
    /// How POV-Ray gets the same scene: a .pov file, or None.
    pov: Option<PovScene>,
}

enum PovScene {
    /// mesh2pov.py on the bunny, with `--subdiv N`.
    Mesh {
        subdiv: u32,
        width: u32,
        height: u32,
    },
    /// A ready .pov file from the peers' folder.
    File(&'static str, u32, u32),
}

#[derive(Debug, Default)]
struct Row {
    scene: String,
    triangles: usize,
    build_s: [f64; 2],
    render_s: [f64; 2],
    /// Process CPU time of the 1-thread build and render: what the work
    /// costs when other processes take turns on the cores.
    build_cpu_s: f64,
    render_cpu_s: f64,
    rays: RayStats,
    /// Each run's 1-thread / 2-thread render time, in run order.
    speedup_runs: Vec<f64>,
    /// Each run's 1-thread CPU nanoseconds per ray, in run order.
    ns_per_ray_runs: Vec<f64>,
    pov_s: [Option<f64>; 2],
    /// POV-Ray's CPU-seconds of its 1-thread trace.
    pov_cpu_s: Option<f64>,
    embree: Option<Embree>,
}

/// Embree's figures for the same mesh scene (medium-quality BVH).
#[derive(Debug, Default, Clone, Copy)]
struct Embree {
    build_s: [f64; 2],
    /// Primary + shadow + shade, Mrays/s.
    mrays: [f64; 2],
}

impl Row {
    fn mrays(&self, t: usize) -> f64 {
        self.rays.total() as f64 / self.render_s[t] / 1e6
    }
    /// On one thread, from CPU time.
    fn ns_per_ray(&self) -> f64 {
        self.render_cpu_s * 1e9 / self.rays.total() as f64
    }
}

pub fn run(args: &BenchArgs) -> Result<()> {
    if args.reps == 0 {
        bail!("--reps: expected at least 1");
    }
    let root = crate::workspace_root();
    let peers = args
        .peers
        .clone()
        .unwrap_or_else(|| root.join("../shared/bench"));
    let povray = !args.no_povray && povray_available();
    if !povray && !args.no_povray {
        eprintln!("povray not found: POV-Ray columns left empty (apt-get install povray)");
    }
    let embree = if args.no_embree {
        None
    } else {
        build_embree(&root, &peers)
    };
    let scenes: Vec<BenchScene> = scenes(&root)?
        .into_iter()
        .filter(|s| args.only.is_empty() || args.only.iter().any(|o| o == s.name))
        .collect();
    let mut rows = measure(&scenes, args.reps)?;
    for (scene, row) in scenes.iter().zip(&mut rows) {
        if povray {
            if let Some(pov) = &scene.pov {
                eprintln!("bench: POV-Ray on {} ...", scene.name);
                let (wall, cpu) = measure_povray(pov, &root, &peers, args.reps)
                    .with_context(|| format!("POV-Ray on {}", scene.name))?;
                (row.pov_s, row.pov_cpu_s) = (wall.map(Some), Some(cpu));
            }
        }
        if let (Some(exe), Some(PovScene::Mesh { subdiv, .. })) = (&embree, &scene.pov) {
            eprintln!("bench: Embree on {} ...", scene.name);
            row.embree = Some(
                run_embree(exe, &root, *subdiv, args.reps)
                    .with_context(|| format!("Embree on {}", scene.name))?,
            );
        }
    }
    print_report(&rows, args.reps);
    Ok(())
}

fn load(path: &Path) -> Result<SceneFile> {
    scene_format::load_path(path).map_err(|e| anyhow::anyhow!("{e}"))
}

fn scenes(root: &Path) -> Result<Vec<BenchScene>> {
    let bunny = load(&root.join("scenes/bench/bunny.toml"))?;
    let mut big = bunny.clone();
    for object in &mut big.objects {
        if let Some(mesh) = object.mesh.as_mut() {
            let data = mesh.data.as_ref().context("bunny mesh not loaded")?;
            mesh.data = Some(Arc::new(subdivide(&subdivide(data))));
        }
    }
    let (w, h) = (bunny.camera.width, bunny.camera.height);
    Ok(vec![
        BenchScene {
            name: "bunny",
            file: bunny,
            pov: Some(PovScene::Mesh {
                subdiv: 0,
                width: w,
                height: h,
            }),
        },
        BenchScene {
            name: "bunny-1.1m",
            file: big,
            pov: Some(PovScene::Mesh {
                subdiv: 2,
                width: w,
                height: h,
            }),
        },
        BenchScene {
            name: "reflectance2",
            file: load(&root.join("scenes/reflectance2.toml"))?,
            pov: Some(PovScene::File("reflectance2.pov", 500, 400)),
        },
    ])
}

/// Splits every triangle 1 -> 4 at its edge midpoints: the same surface,
/// four times the triangles (the peers' `--subdiv`).
pub fn subdivide(data: &MeshData) -> MeshData {
    let mid = |a: [f32; 3], b: [f32; 3]| {
        [
            (a[0] + b[0]) * 0.5,
            (a[1] + b[1]) * 0.5,
            (a[2] + b[2]) * 0.5,
        ]
    };
    let mut triangles = Vec::with_capacity(data.triangles.len() * 4);
    for &[a, b, c] in &data.triangles {
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    MeshData {
        triangles,
        skipped_degenerate: data.skipped_degenerate,
    }
}

fn pool(threads: usize) -> Result<rayon::ThreadPool> {
    Ok(rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?)
}

/// "lowest-highest" of a run's figures.
fn spread(xs: &[f64]) -> String {
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    format!("{lo:.2}x-{hi:.2}x")
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// One run of one scene: build and render on 1 thread, then on 2.
#[derive(Debug, Clone, Copy, Default)]
struct Run {
    build_s: [f64; 2],
    render_s: [f64; 2],
    build_cpu_s: f64,
    render_cpu_s: f64,
    rays: RayStats,
}

/// Runs every scene `reps` times, taking turns: run r of each scene and its
/// 1- and 2-thread halves are measured close together in time, so the
/// ratios between them (speed-up, cost at 1.1M / at 70k) are taken within a
/// run, where the machine's slow swings in speed cancel out.
fn measure(scenes: &[BenchScene], reps: usize) -> Result<Vec<Row>> {
    let prepared = scenes
        .iter()
        .map(|s| prepare(&s.file).map_err(|e| anyhow::anyhow!("{e}")))
        .collect::<Result<Vec<_>>>()?;
    let pools = [pool(THREADS[0])?, pool(THREADS[1])?];
    let mut runs = vec![Vec::new(); scenes.len()];
    for rep in 0..reps {
        eprintln!("bench: run {} of {reps} ...", rep + 1);
        for (scene, runs) in prepared.iter().zip(&mut runs) {
            runs.push(measure_run(scene, &pools));
        }
    }
    Ok(scenes
        .iter()
        .zip(&prepared)
        .zip(runs)
        .map(|((s, p), runs)| summarise(s.name, p.objects().len(), &runs))
        .collect())
}

fn measure_run(scene: &Scene, pools: &[rayon::ThreadPool; 2]) -> Run {
    let mut run = Run::default();
    for (t, pool) in pools.iter().enumerate() {
        let (start, cpu) = (Instant::now(), cpu_time());
        let bvh = pool.install(|| Bvh::build(scene.objects()));
        run.build_s[t] = start.elapsed().as_secs_f64();
        let build_cpu = cpu_time() - cpu;
        drop(bvh);
        let (start, cpu) = (Instant::now(), cpu_time());
        let job = RenderJob::full(scene);
        let rendered = pool.install(|| render(scene, &job, &|_| {}));
        let (image, rays) = (rendered.image, rendered.rays);
        run.render_s[t] = start.elapsed().as_secs_f64();
        let render_cpu = cpu_time() - cpu;
        drop(image);
        if t == 0 {
            (run.build_cpu_s, run.render_cpu_s) = (build_cpu, render_cpu);
        }
        run.rays = rays;
    }
    run
}

/// Medians of the runs, and the median of each run's own speed-up.
fn summarise(name: &str, triangles: usize, runs: &[Run]) -> Row {
    let med = |f: &dyn Fn(&Run) -> f64| median(runs.iter().map(f).collect());
    let rays = runs[0].rays;
    Row {
        scene: name.to_string(),
        triangles,
        build_s: [med(&|r| r.build_s[0]), med(&|r| r.build_s[1])],
        render_s: [med(&|r| r.render_s[0]), med(&|r| r.render_s[1])],
        build_cpu_s: med(&|r| r.build_cpu_s),
        render_cpu_s: med(&|r| r.render_cpu_s),
        rays,
        speedup_runs: runs.iter().map(|r| r.render_s[0] / r.render_s[1]).collect(),
        ns_per_ray_runs: runs
            .iter()
            .map(|r| r.render_cpu_s * 1e9 / rays.total() as f64)
            .collect(),
        ..Row::default()
    }
}

/// Compiles the peers' `embree_bench.cpp` into `target/peers/` once; None
/// (with a note) when Embree or g++ is missing.
fn build_embree(root: &Path, peers: &Path) -> Option<PathBuf> {
    let exe = root.join("target/peers/embree_bench");
    let source = peers.join("embree_bench.cpp");
    if exe.is_file() {
        return Some(exe);
    }
    if !Path::new("/usr/include/embree3/rtcore.h").is_file() || !source.is_file() {
        eprintln!("Embree not found: its columns left empty (apt-get install libembree-dev g++)");
        return None;
    }
    eprintln!("bench: compiling {} ...", source.display());
    std::fs::create_dir_all(exe.parent()?).ok()?;
    let built = Command::new("g++")
        .args(["-O3", "-march=native", "-std=c++17"])
        .arg(&source)
        .arg("-o")
        .arg(&exe)
        .args(["-lembree3", "-lpthread"])
        .status();
    match built {
        Ok(status) if status.success() => Some(exe),
        _ => {
            eprintln!("could not compile embree_bench: Embree columns left empty");
            None
        }
    }
}

fn run_embree(exe: &Path, root: &Path, subdiv: u32, reps: usize) -> Result<Embree> {
    let out = Command::new(exe)
        .arg(root.join("scenes/bench/bunny.obj"))
        .args(["--reps", &reps.to_string(), "--subdiv", &subdiv.to_string()])
        .output()
        .context("run embree_bench")?;
    let text = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        bail!(
            "embree_bench failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    parse_embree(&text).with_context(|| format!("unexpected embree_bench output:\n{text}"))
}

/// Reads the medium-quality sections of embree_bench's report.
fn parse_embree(text: &str) -> Option<Embree> {
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

/// CPU seconds this process has used, on all its threads.
fn cpu_time() -> f64 {
    // SAFETY: getrusage only writes the struct it is given.
    let usage = unsafe {
        let mut usage = std::mem::zeroed::<libc::rusage>();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        usage
    };
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    seconds(usage.ru_utime) + seconds(usage.ru_stime)
}

fn povray_available() -> bool {
    Command::new("povray")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success() || !o.stderr.is_empty())
}

/// POV-Ray's render-only wall time on 1 and 2 threads and its CPU time on
/// 1 thread, medians.
fn measure_povray(
    pov: &PovScene,
    root: &Path,
    peers: &Path,
    reps: usize,
) -> Result<([f64; 2], f64)> {
    let dir = tempfile::tempdir()?;
    let (file, w, h) = match pov {
        PovScene::Mesh {
            subdiv,
            width,
            height,
        } => {
            let out = dir.path().join("scene.pov");
            let status = Command::new("python3")
                .arg(peers.join("mesh2pov.py"))
                .arg(root.join("scenes/bench/bunny.obj"))
                .arg(&out)
                .args(["--subdiv", &subdiv.to_string()])
                .output()
                .context("run mesh2pov.py (python3 with numpy)")?;
            if !status.status.success() {
                bail!(
                    "mesh2pov.py failed: {}",
                    String::from_utf8_lossy(&status.stderr)
                );
            }
            (out, *width, *height)
        }
        PovScene::File(name, w, h) => (peers.join(name), *w, *h),
    };
    let (mut wall, mut cpu) = ([0.0; 2], 0.0);
    for (t, &threads) in THREADS.iter().enumerate() {
        let (mut walls, mut cpus) = (Vec::new(), Vec::new());
        for _ in 0..reps {
            let (w, c) = povray_trace_time(&file, w, h, threads, dir.path())?;
            walls.push(w);
            cpus.push(c);
        }
        wall[t] = median(walls);
        if threads == 1 {
            cpu = median(cpus);
        }
    }
    Ok((wall, cpu))
}

/// Runs POV-Ray once and reads its own "Trace Time" (render only, without
/// its start-up and parsing): wall and CPU seconds.
fn povray_trace_time(pov: &Path, w: u32, h: u32, threads: usize, dir: &Path) -> Result<(f64, f64)> {
    let out = Command::new("povray")
        .arg(format!("+I{}", pov.display()))
        .arg(format!("+O{}", dir.join("pov.png").display()))
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

fn print_report(rows: &[Row], reps: usize) {
    println!(
        "Medians of {reps} runs, the scenes taking turns. Rays: primary + shadow + reflected.\n"
    );
    println!(
        "| scene | objects | BVH build 1 / 2 thr | render 1 thr | render 2 thr | Mrays/s 1 / 2 thr | 2-thr speed-up | POV-Ray 1 / 2 thr | POV-Ray / ours, 1 thr |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        let pov = match r.pov_s {
            [Some(a), Some(b)] => format!("{a:.3} s / {b:.3} s"),
            _ => "-".to_string(),
        };
        let ratio = r.pov_s[0].map_or("-".to_string(), |p| format!("{:.2}x", p / r.render_s[0]));
        println!(
            "| {} | {} | {:.3} s / {:.3} s | {:.3} s | {:.3} s | {:.2} / {:.2} | {:.2}x | {} | {} |",
            r.scene,
            r.triangles,
            r.build_s[0],
            r.build_s[1],
            r.render_s[0],
            r.render_s[1],
            r.mrays(0),
            r.mrays(1),
            median(r.speedup_runs.clone()),
            pov,
            ratio
        );
    }
    println!("\nOne thread, CPU time of this process (less sensitive to other load):\n");
    println!("| scene | rays (nearest + shadow) | BVH build CPU | render CPU | Mrays per CPU-s | ns per ray | POV-Ray CPU | POV-Ray / ours, CPU |");
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        let (pov, ratio) = r.pov_cpu_s.map_or(("-".into(), "-".into()), |p| {
            (format!("{p:.3} s"), format!("{:.2}x", p / r.render_cpu_s))
        });
        println!(
            "| {} | {} + {} | {:.3} s | {:.3} s | {:.2} | {:.1} | {} | {} |",
            r.scene,
            r.rays.nearest,
            r.rays.shadow,
            r.build_cpu_s,
            r.render_cpu_s,
            r.rays.total() as f64 / r.render_cpu_s / 1e6,
            r.ns_per_ray(),
            pov,
            ratio
        );
    }
    if rows.iter().any(|r| r.embree.is_some()) {
        println!("\nEmbree 3 (embree_bench, medium quality, rtcIntersect1 + rtcOccluded1 + shade), same run:\n");
        println!(
            "| scene | Embree build 1 / 2 thr | Embree Mrays/s 1 / 2 thr | ours / Embree, 1 thr |"
        );
        println!("| --- | ---: | ---: | ---: |");
        for r in rows {
            if let Some(e) = r.embree {
                println!(
                    "| {} | {:.3} s / {:.3} s | {:.2} / {:.2} | {:.2} |",
                    r.scene,
                    e.build_s[0],
                    e.build_s[1],
                    e.mrays[0],
                    e.mrays[1],
                    r.mrays(0) / e.mrays[0]
                );
            }
        }
    }
    println!();
    let find = |name: &str| rows.iter().find(|r| r.scene == name);
    if let (Some(small), Some(big)) = (find("bunny"), find("bunny-1.1m")) {
        let ratios: Vec<f64> = big
            .ns_per_ray_runs
            .iter()
            .zip(&small.ns_per_ray_runs)
            .map(|(b, s)| b / s)
            .collect();
        let embree = match (small.embree, big.embree) {
            (Some(s), Some(b)) => format!("; Embree's: {:.2}x", s.mrays[0] / b.mrays[0]),
            _ => String::new(),
        };
        println!(
            "target: per-ray cost at 1.1M / at 70k triangles <= 1.5x: {:.2}x (CPU time, median of each run's ratio; runs {}{embree})",
            median(ratios.clone()),
            spread(&ratios)
        );
        println!(
            "target: BVH build of {} triangles < 1 s: {:.3} s wall, {:.3} s CPU on 1 thread; {:.3} s on 2",
            big.triangles, big.build_s[0], big.build_cpu_s, big.build_s[1]
        );
    }
    if let Some(b) = find("bunny") {
        println!(
            "target: bunny, 1 thread, >= 5.5 Mrays/s (half of Embree's ~11): {:.2} wall, {:.2} per CPU-s",
            b.mrays(0),
            b.rays.total() as f64 / b.render_cpu_s / 1e6
        );
        let embree = b.embree.map_or(String::new(), |e| {
            format!("; Embree's: {:.2}x", e.mrays[1] / e.mrays[0])
        });
        println!(
            "target: 2-thread speed-up >= 1.8x: {:.2}x (median of each run's; runs {}{embree})",
            median(b.speedup_runs.clone()),
            spread(&b.speedup_runs)
        );
        if let (Some(p), Some(c)) = (b.pov_s[0], b.pov_cpu_s) {
            println!(
                "target: bunny, 1 thread, >= 3x POV-Ray render-only: {:.2}x wall, {:.2}x CPU",
                p / b.render_s[0],
                c / b.render_cpu_s
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subdivision_quarters_each_triangle_on_the_same_surface() {
        let data = MeshData {
            triangles: vec![[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]],
            skipped_degenerate: 0,
        };
        let twice = subdivide(&subdivide(&data));
        assert_eq!(twice.triangles.len(), 16);
        let area = |[a, b, c]: &[[f32; 3]; 3]| {
            ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2.0
        };
        // Same orientation and total area (2) as the original.
        assert!(twice.triangles.iter().all(|t| area(t) == 0.125));
    }

    #[test]
    fn embree_figures_are_read_from_its_report() {
        let text = "[quality=medium threads=1] BVH build (rtcCommitScene) median 63.9 ms  (1.09 Mtris/s)\n\
            primary rtcIntersect1   232.25 ms/frame      8.93 Mrays/s  (hits 510496 = 24.6%)\n\
            primary1 + shadow rtcOccluded1 + shade   357.65 ms/frame      7.13 Mrays/s  (hits)\n\
            [quality=medium threads=2] BVH build (rtcCommitScene) median 48.7 ms  (1.43 Mtris/s)\n\
            primary1 + shadow rtcOccluded1 + shade   200.00 ms/frame     12.50 Mrays/s  (hits)\n\
            [quality=high threads=1] BVH build (rtcCommitScene) median 256.6 ms  (0.27 Mtris/s)\n\
            primary1 + shadow rtcOccluded1 + shade   361.86 ms/frame      7.05 Mrays/s  (hits)\n";
        let e = parse_embree(text).expect("parsed");
        assert_eq!(e.build_s, [0.0639, 0.0487]);
        assert_eq!(e.mrays, [7.13, 12.5]);
        assert!(parse_embree("[quality=medium threads=1] nothing").is_none());
    }

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
