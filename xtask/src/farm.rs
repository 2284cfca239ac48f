//! `cargo xtask farm-test`: a scene rendered as N tiles, each by a `tracer`
//! process of its own (as a scheduler's tasks would), merged with `tracer
//! merge`, and compared with a single render bit for bit; the tasks' summed
//! time against the single render's is the split's cost. With `--slurm`
//! the tiles and the merge are `farm/slurm/*.sbatch` jobs of a real
//! single-node Slurm started for the test ([`slurm`]).

pub mod slurm;

use anyhow::{bail, ensure, Context, Result};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[derive(Args)]
pub struct FarmArgs {
    /// The scene [default: scenes/depth-of-field.toml, lens blur and 64
    /// samples per pixel]
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// Tile counts to try, each merged and compared
    #[arg(long, value_delimiter = ',', default_value = "1,4,7")]
    pub tiles: Vec<u32>,
    /// Image width (the height follows) [default: the scene's]
    #[arg(long)]
    pub width: Option<u32>,
    /// Samples per pixel [default: the scene's]
    #[arg(long)]
    pub samples: Option<u32>,
    /// Run the tiles and the merge as jobs of a real Slurm on this machine
    /// (farm/slurm/*.sbatch with `sbatch --wait`): as root, installs
    /// Debian's slurmctld, slurmd, slurm-client and munge if missing, starts
    /// a private single-node cluster and stops it afterwards
    #[arg(long)]
    pub slurm: bool,
    /// Tiles prepare the scene each (as before `tracer render --cache`),
    /// instead of the first keeping it for the others
    #[arg(long)]
    pub no_cache: bool,
    /// Times to run the single render and every tile count, taking turns
    /// (the machine's noise moves one run's overhead by several percent);
    /// the median overhead of each count is printed last
    #[arg(long, default_value = "1", value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: u32,
}

pub fn run(args: &FarmArgs) -> Result<()> {
    if args.slurm {
        slurm::ensure_root()?;
    }
    let root = crate::workspace_root();
    let scene = args
        .scene
        .clone()
        .unwrap_or_else(|| root.join("scenes/depth-of-field.toml"));
    let tracer = build_tracer(&root)?;
    let dir = tempfile::tempdir().context("cannot make a folder for the tiles")?;
    let mut size: Vec<String> = Vec::new();
    if let Some(w) = args.width {
        size.extend(["--width".to_string(), w.to_string()]);
    }
    if let Some(s) = args.samples {
        size.extend(["--samples".to_string(), s.to_string()]);
    }
    ensure!(
        args.tiles.iter().all(|&n| n > 0),
        "--tiles: expected counts of at least 1"
    );
    let single = dir.path().join("single.exr");
    let job = Job {
        tracer: &tracer,
        scene: &scene,
        dir: dir.path(),
        size: &size,
        single: &single,
    };
    if args.slurm {
        single_render(&job)?;
        // Slurm runs the scripts in another folder.
        let scene = std::path::absolute(&scene).context("cannot find the scene")?;
        let job = Job {
            scene: &scene,
            ..job
        };
        return run_slurm(&root, &job, &args.tiles);
    }
    let mut overheads = vec![Vec::new(); args.tiles.len()];
    for rep in 0..args.reps {
        let single_cost = single_render(&job)?;
        for (k, &n) in args.tiles.iter().enumerate() {
            let cache = (!args.no_cache).then(|| dir.path().join(format!("prepared-{n}-{rep}")));
            let cost = tiles_merged(&job, n, cache)?;
            let over = |tiles: f64, one: f64| 100.0 * (tiles / one - 1.0);
            let (wall, cpu) = (
                over(cost.wall, single_cost.wall),
                over(cost.cpu, single_cost.cpu),
            );
            println!(
                "{n:>3} tiles: merged = single render, bit for bit; tasks {:.3} s in all, \
                 {wall:+.1} % against the single render ({:.3} s of CPU, {cpu:+.1} %)",
                cost.wall, cost.cpu,
            );
            overheads[k].push((wall, cpu));
        }
    }
    if args.reps > 1 {
        for (&n, runs) in args.tiles.iter().zip(&overheads) {
            let median = |f: fn(&(f64, f64)) -> f64| {
                let mut v: Vec<f64> = runs.iter().map(f).collect();
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            };
            println!(
                "{n:>3} tiles, median of {} runs: {:+.1} % wall, {:+.1} % CPU against the single render",
                runs.len(),
                median(|r| r.0),
                median(|r| r.1)
            );
        }
    }
    Ok(())
}

/// What every run of the test renders, and where.
#[derive(Clone, Copy)]
struct Job<'a> {
    tracer: &'a Path,
    scene: &'a Path,
    dir: &'a Path,
    size: &'a [String],
    single: &'a Path,
}

/// The whole image in one process, as the tiles are compared with.
fn single_render(job: &Job) -> Result<Cost> {
    let start = Cost::now();
    let args = [&path_arg(job.scene), "-o", &path_arg(job.single)];
    tracer_run(job.tracer, &args, job.size)?;
    let cost = start.since();
    println!(
        "single render: {:.3} s ({:.3} s of CPU)",
        cost.wall, cost.cpu
    );
    Ok(cost)
}

/// N tiles, merged and compared with the single render: their cost.
fn tiles_merged(job: &Job, n: u32, cache: Option<PathBuf>) -> Result<Cost> {
    let (tiles, cost) = render_tiles(job.tracer, job.scene, n, job.dir, job.size, cache)?;
    let merged = job.dir.join(format!("merged-{n}.exr"));
    let mut merge: Vec<String> = vec!["merge".into()];
    merge.extend(tiles.iter().map(|t| path_arg(t)));
    merge.extend(["-o".into(), path_arg(&merged)]);
    run_checked(Command::new(job.tracer).args(&merge))?;
    same_as_single(job.single, &merged, n)?;
    Ok(cost)
}

/// Renders tile I/N for every I, one process each, one after the other
/// (a farm runs them side by side; their sum is what it pays). Every
/// render here is on one thread, so the times compare; that the thread
/// count changes no pixel is the tile tests' part. With a `cache` folder
/// (empty), the first task prepares the scene and keeps it there, and the
/// others read it, as the farm scripts do.
fn render_tiles(
    tracer: &Path,
    scene: &Path,
    n: u32,
    dir: &Path,
    size: &[String],
    cache: Option<PathBuf>,
) -> Result<(Vec<PathBuf>, Cost)> {
    let mut tiles = Vec::new();
    let mut cost = Cost::default();
    for i in 0..n {
        let tile = dir.join(format!("tile-{n}-{i}.exr"));
        let spec = format!("{i}/{n}");
        let mut args = vec![
            path_arg(scene),
            "--tile".into(),
            spec,
            "-o".into(),
            path_arg(&tile),
        ];
        if let Some(cache) = &cache {
            args.extend(["--cache".into(), path_arg(cache)]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let start = Cost::now();
        tracer_run(tracer, &args, size)?;
        let task = start.since();
        (cost.wall, cost.cpu) = (cost.wall + task.wall, cost.cpu + task.cpu);
        tiles.push(tile);
    }
    Ok((tiles, cost))
}

/// Installs and starts Slurm, runs the array and the merge for each tile
/// count, compares; the cluster stops when dropped, on failure too.
fn run_slurm(root: &Path, job: &Job, counts: &[u32]) -> Result<()> {
    let start = Instant::now();
    let installed = slurm::install()?;
    println!("slurm install: {:.1} s ({installed})", seconds(start));
    let start = Instant::now();
    let cluster = slurm::Cluster::start()?;
    let node = &cluster.node;
    println!(
        "slurm start: {:.1} s (munged, slurmctld, slurmd; node {} idle, {} CPUs, {} MB)",
        seconds(start),
        node.name,
        node.cpus,
        node.memory_mb
    );
    for &n in counts {
        slurm_tiles(&cluster, root, job, n)?;
    }
    let start = Instant::now();
    drop(cluster);
    println!("slurm stop: {:.1} s", seconds(start));
    Ok(())
}

/// One tile count: `sbatch --wait --array=0-(N-1) tiles.sbatch`, then
/// `sbatch --wait --dependency=afterok:ID merge.sbatch`, as docs/src/guide/farm.md
/// has them.
fn slurm_tiles(cluster: &slurm::Cluster, root: &Path, job: &Job, n: u32) -> Result<()> {
    let scripts = root.join("farm/slurm");
    let logs = cluster.jobs_dir();
    let tiles = job.dir.join(format!("slurm-tiles-{n}"));
    let merged = job.dir.join(format!("slurm-merged-{n}.exr"));
    let mut array = vec![
        format!("--array=0-{}", n - 1),
        // The script asks for 4; this node may have fewer.
        "--cpus-per-task=1".into(),
        format!("--output={}/tiles-%A_%a.log", logs.display()),
        format!("--export=ALL,TRACER={}", job.tracer.display()),
        path_arg(&scripts.join("tiles.sbatch")),
        path_arg(job.scene),
        n.to_string(),
        path_arg(&tiles),
    ];
    array.extend(job.size.iter().cloned());
    let start = Instant::now();
    let tiles_job = cluster.sbatch_wait(&array)?;
    let array_seconds = seconds(start);
    let merge = [
        format!("--dependency=afterok:{}", tiles_job.id),
        format!("--output={}/merge-%j.log", logs.display()),
        format!("--export=ALL,TRACER={}", job.tracer.display()),
        path_arg(&scripts.join("merge.sbatch")),
        path_arg(&tiles),
        path_arg(&merged),
    ];
    let start = Instant::now();
    let merge_job = cluster.sbatch_wait(&merge)?;
    let merge_seconds = seconds(start);
    same_as_single(job.single, &merged, n)?;
    println!("{n:>3} tiles: merged = single render, bit for bit");
    let report = |what: &str, wall: f64, span: &slurm::Span| {
        println!(
            "      {what} sbatch --wait {wall:.1} s (queued {} s, ran {} s)",
            span.queued, span.ran
        );
    };
    report(
        &format!("array 0-{}:", n - 1),
        array_seconds,
        &tiles_job.span,
    );
    report("merge:", merge_seconds, &merge_job.span);
    Ok(())
}

/// Wall and CPU seconds of the `tracer` processes run: the CPU time
/// (user and system, of the children waited for) moves less with the
/// machine's other load.
#[derive(Debug, Clone, Copy, Default)]
struct Cost {
    wall: f64,
    cpu: f64,
}

/// When a cost began to count.
struct Start {
    at: Instant,
    cpu: f64,
}

impl Cost {
    fn now() -> Start {
        Start {
            at: Instant::now(),
            cpu: children_cpu(),
        }
    }
}

impl Start {
    fn since(&self) -> Cost {
        Cost {
            wall: seconds(self.at),
            cpu: children_cpu() - self.cpu,
        }
    }
}

fn children_cpu() -> f64 {
    use crate::bench::rusage;
    rusage::cpu_seconds(&rusage::of(libc::RUSAGE_CHILDREN))
}

fn seconds(start: Instant) -> f64 {
    start.elapsed().as_secs_f64()
}

fn same_as_single(single: &Path, merged: &Path, n: u32) -> Result<()> {
    ensure!(
        same_values(single, merged)?,
        "{n} tiles merged differ from the single render"
    );
    Ok(())
}

/// Whether two EXR files hold the same values to the bit.
fn same_values(a: &Path, b: &Path) -> Result<bool> {
    let read = |p: &Path| -> Result<Vec<u32>> {
        let image = image::open(p).with_context(|| format!("cannot read {}", p.display()))?;
        Ok(image
            .to_rgb32f()
            .into_raw()
            .iter()
            .map(|x| x.to_bits())
            .collect())
    };
    Ok(read(a)? == read(b)?)
}

fn tracer_run(tracer: &Path, args: &[&str], size: &[String]) -> Result<()> {
    run_checked(
        Command::new(tracer)
            .arg("render")
            .args(args)
            .args(size)
            .args(["--threads", "1", "--quiet"]),
    )
}

fn run_checked(command: &mut Command) -> Result<()> {
    let out = command.output().context("cannot run tracer")?;
    if !out.status.success() {
        bail!(
            "{command:?} failed ({}):\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
    }
    Ok(())
}

/// Builds the `tracer` binary as a user would, and returns its path.
pub(crate) fn build_tracer(root: &Path) -> Result<PathBuf> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    run_checked(Command::new(cargo).current_dir(root).args([
        "build",
        "--release",
        "--quiet",
        "--bin",
        "tracer",
    ]))?;
    Ok(crate::target_dir().join("release/tracer"))
}

fn path_arg(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}
