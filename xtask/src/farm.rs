//! `cargo xtask farm-test`: a scene rendered as N tiles, each by a `tracer`
//! process of its own (as a scheduler's tasks would), merged with `tracer
//! merge`, and compared with a single render bit for bit; the tasks' summed
//! time against the single render's is the split's cost.

use anyhow::{bail, ensure, Context, Result};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[derive(Args)]
pub struct FarmArgs {
    /// The scene [default: scenes/depth-of-field.toml, lens blur and 4
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
}

pub fn run(args: &FarmArgs) -> Result<()> {
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
    let single = dir.path().join("single.exr");
    let start = Instant::now();
    tracer_run(
        &tracer,
        &[&path_arg(&scene), "-o", &path_arg(&single)],
        &size,
    )?;
    let single_seconds = start.elapsed().as_secs_f64();
    println!("single render: {single_seconds:.3} s");
    for &n in &args.tiles {
        ensure!(n > 0, "--tiles: expected counts of at least 1");
        let (tiles, seconds) = render_tiles(&tracer, &scene, n, dir.path(), &size)?;
        let merged = dir.path().join(format!("merged-{n}.exr"));
        let mut merge: Vec<String> = vec!["merge".into()];
        merge.extend(tiles.iter().map(|t| path_arg(t)));
        merge.extend(["-o".into(), path_arg(&merged)]);
        run_checked(Command::new(&tracer).args(&merge))?;
        ensure!(
            same_values(&single, &merged)?,
            "{n} tiles merged differ from the single render"
        );
        println!(
            "{n:>3} tiles: merged = single render, bit for bit; tasks {seconds:.3} s in all, \
             {:+.1} % against the single render",
            100.0 * (seconds / single_seconds - 1.0)
        );
    }
    Ok(())
}

/// Renders tile I/N for every I, one process each, one after the other
/// (a farm runs them side by side; their sum is what it pays). Every
/// render here is on one thread, so the times compare; that the thread
/// count changes no pixel is the tile tests' part.
fn render_tiles(
    tracer: &Path,
    scene: &Path,
    n: u32,
    dir: &Path,
    size: &[String],
) -> Result<(Vec<PathBuf>, f64)> {
    let mut tiles = Vec::new();
    let mut seconds = 0.0;
    for i in 0..n {
        let tile = dir.join(format!("tile-{n}-{i}.exr"));
        let spec = format!("{i}/{n}");
        let args = [&path_arg(scene), "--tile", &spec, "-o", &path_arg(&tile)];
        let start = Instant::now();
        tracer_run(tracer, &args, size)?;
        seconds += start.elapsed().as_secs_f64();
        tiles.push(tile);
    }
    Ok((tiles, seconds))
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
fn build_tracer(root: &Path) -> Result<PathBuf> {
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
