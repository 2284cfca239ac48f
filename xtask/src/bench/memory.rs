//! Peak memory of whole `tracer render` processes (loading, preparing, the
//! BVHs, the image, encoding): the bunny scene against a scene of 1,000
//! bunnies placing the same OBJ, each its own size and turn (issue 16:
//! under twice the one bunny's), and the 1.1M-triangle bunny on 1 and 2
//! threads against Embree's harness (issue 16: no more than it holds).
//!
//! Each is measured as a child of a small process (`cargo xtask peak-of`,
//! started afresh): Linux carries a process's resident high-water mark
//! across `exec` into the child's `ru_maxrss`, so a child of the bench
//! itself (which holds the 1.1M-triangle scene) reported the bench's peak.

use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The bunnies of the instancing scene: a 10 x 10 x 10 grid.
const GRID: usize = 10;

/// One `tracer render` process, measured.
#[derive(Debug, Clone, Copy)]
pub struct Process {
    /// Peak resident memory, bytes.
    pub peak_bytes: u64,
    pub wall_s: f64,
    /// User + system CPU time.
    pub cpu_s: f64,
}

/// The one bunny and the 1,000 bunnies, each rendered on one thread; the
/// 1.1M-triangle bunny on 1 and 2 threads, and Embree's harness on it.
#[derive(Debug, Clone, Copy)]
pub struct Instancing {
    pub one: Process,
    pub many: Process,
    /// Bunnies in the second scene, and triangles they place.
    pub copies: usize,
    pub virtual_triangles: usize,
    pub big: [Process; 2],
    pub embree: Option<Process>,
}

/// Renders the scenes once each with `tracer` (built first, as a user
/// would), the 1,000 bunnies and the 1.1M bunny's scene written into
/// `target/bench/` (its OBJ already there: `scenes::scenes` writes it);
/// `embree` is the built harness, when there is one.
pub fn measure(root: &Path, embree: Option<&Path>) -> Result<Instancing> {
    let tracer = crate::farm::build_tracer(root)?;
    let bunny = root.join("scenes/bench/bunny.toml");
    let many_scene = scene_path();
    let dir = many_scene.parent().context("no folder")?;
    std::fs::create_dir_all(dir)?;
    let obj = root.join(super::scenes::BUNNY_OBJ);
    std::fs::write(&many_scene, bunnies(&obj)?)?;
    let out = dir.join("instancing.png");
    eprintln!("bench: peak memory of one bunny ...");
    let one = render(&tracer, &bunny, &out)?;
    eprintln!("bench: peak memory of {} bunnies ...", GRID.pow(3));
    let many = render(&tracer, &many_scene, &out)?;
    let big_obj = crate::target_dir().join("bench/bunny-1.1m.obj");
    let big_scene = dir.join("bunny-1.1m.toml");
    std::fs::write(&big_scene, one_mesh(&bunny, &big_obj)?)?;
    eprintln!("bench: peak memory of the 1.1M-triangle bunny ...");
    let big = [
        render_on(&tracer, &big_scene, &out, 1)?,
        render_on(&tracer, &big_scene, &out, 2)?,
    ];
    let embree = match embree {
        Some(exe) => {
            eprintln!("bench: peak memory of Embree's harness on it ...");
            let args = ["--reps", "1", "--subdiv", "2"];
            let mut command = vec![exe.into(), root.join(super::scenes::BUNNY_OBJ).into()];
            command.extend(args.map(Into::into));
            Some(measured(&command)?)
        }
        None => None,
    };
    let triangles = scene_format::obj::read_obj(&obj)
        .map_err(|e| anyhow::anyhow!("{e}"))?
        .triangles
        .len();
    Ok(Instancing {
        one,
        many,
        copies: GRID.pow(3),
        virtual_triangles: triangles * GRID.pow(3),
        big,
        embree,
    })
}

/// The bench bunny's scene with its mesh the file `obj`.
fn one_mesh(scene: &Path, obj: &Path) -> Result<String> {
    let text = std::fs::read_to_string(scene)?;
    let obj = toml::Value::String(obj.to_str().context("a path not UTF-8")?.to_string());
    let with = text.replace("obj = \"bunny.obj\"", &format!("obj = {obj}"));
    if with == text {
        bail!("{}: no `obj = \"bunny.obj\"` to replace", scene.display());
    }
    Ok(with)
}

/// The bunny scene's camera, image, light and material, its bunny placed
/// on a grid of 1,000, each smaller, turned its own way, every seventh
/// mirrored; all name `obj`, so they share one mesh.
fn bunnies(obj: &Path) -> Result<String> {
    let mut text = String::from(
        "# Written by `cargo xtask bench`: 1,000 instances of the bench bunny.\n\
         [camera]\neye = [14, 11, 18]\nlook_at = [0, 0, 0]\nfov = 50\nwidth = 1920\nheight = 1080\n\n\
         [render]\nbackground = [0.1, 0.1, 0.15]\n\n\
         [[lights]]\nposition = [20, 30, 25]\n\n\
         [materials.clay]\nambient = [0.09, 0.085, 0.075]\ndiffuse = [0.81, 0.765, 0.675]\n",
    );
    let obj = obj.to_str().context("the bunny's path is not UTF-8")?;
    let obj = toml::Value::String(obj.to_string());
    for i in 0..GRID.pow(3) {
        let cell = [i / (GRID * GRID), i / GRID % GRID, i % GRID];
        let at = cell.map(|c| (c as f32 - (GRID as f32 - 1.0) / 2.0) * 1.1);
        let s = 0.3 + 0.025 * (i * 7 % 5) as f32;
        let mirror = if i % 7 == 0 { -1.0 } else { 1.0 };
        let turn = [i * 37 % 360, i * 53 % 360, i * 11 % 90];
        writeln!(
            text,
            "\n[[objects]]\nmesh = {{ obj = {obj} }}\nmaterial = \"clay\"\n\
             transform = {{ translate = {at:?}, rotate = {turn:?}, scale = [{}, {s}, {}] }}",
            mirror * s,
            s * 1.2
        )?;
    }
    Ok(text)
}

/// Renders `scene` to `out` on one thread and measures the process.
fn render(tracer: &Path, scene: &Path, out: &Path) -> Result<Process> {
    render_on(tracer, scene, out, 1)
}

/// Renders `scene` to `out` on `threads` threads and measures the process.
fn render_on(tracer: &Path, scene: &Path, out: &Path, threads: usize) -> Result<Process> {
    let threads = threads.to_string();
    let mut command = vec![tracer.into(), "render".into(), scene.into(), "-o".into()];
    command.extend([
        out.into(),
        "--threads".into(),
        threads.into(),
        "--quiet".into(),
    ]);
    measured(&command)
}

/// `command` run by `cargo xtask peak-of`, started afresh (see the module's
/// comment), and what that printed of it.
fn measured(command: &[std::ffi::OsString]) -> Result<Process> {
    let text = super::process::stdout_of(
        Command::new(std::env::current_exe()?)
            .arg("peak-of")
            .args(command),
        &format!("{command:?} under `xtask peak-of`"),
    )?;
    parse_process(&text).with_context(|| format!("`xtask peak-of` printed {text:?}"))
}

/// "peak_bytes wall_s cpu_s", as `peak_of` prints it.
fn parse_process(text: &str) -> Option<Process> {
    let mut words = text.split_whitespace();
    let mut next = || words.next()?.parse::<f64>().ok();
    let (peak, wall_s, cpu_s) = (next()?, next()?, next()?);
    Some(Process {
        peak_bytes: peak as u64,
        wall_s,
        cpu_s,
    })
}

/// Runs `command` (quiet), waits for it and prints its peak resident memory
/// in bytes, wall and CPU seconds: `cargo xtask peak-of`, for the bench.
pub fn peak_of(command: &[std::ffi::OsString]) -> Result<()> {
    let start = Instant::now();
    let child = Command::new(&command[0])
        .args(&command[1..])
        .stdout(std::process::Stdio::null())
        .spawn()
        .with_context(|| format!("running {:?}", command[0]))?;
    let (status, usage) = super::rusage::wait(child.id())?;
    let wall_s = start.elapsed().as_secs_f64();
    if status != 0 {
        bail!("{command:?} failed");
    }
    // Linux gives kilobytes.
    let peak = usage.ru_maxrss as u64 * 1024;
    let cpu = super::rusage::cpu_seconds(&usage);
    println!("{peak} {wall_s} {cpu}");
    Ok(())
}

/// The report's section.
pub fn report(m: &Instancing) {
    let mb = |b: u64| b as f64 / 1e6;
    println!("\nMemory: one `tracer render` process each, 1920x1080 (loading, preparing, BVHs, image, encoding; peak resident memory from wait4):\n");
    println!("| scene | peak memory | wall | CPU |");
    println!("| --- | ---: | ---: | ---: |");
    let mut rows = vec![
        ("bunny, 1 thread", m.one),
        ("bunnies-1000, 1 thread", m.many),
        ("bunny-1.1m, 1 thread", m.big[0]),
        ("bunny-1.1m, 2 threads", m.big[1]),
    ];
    rows.extend(m.embree.map(|e| ("bunny-1.1m, Embree's harness", e)));
    for (name, p) in rows {
        println!(
            "| {name} | {:.1} MB | {:.3} s | {:.3} s |",
            mb(p.peak_bytes),
            p.wall_s,
            p.cpu_s
        );
    }
    println!(
        "\ntarget: {} bunnies ({} virtual triangles), peak memory < 2x one bunny's: {:.1} MB / {:.1} MB = {:.2}x",
        m.copies,
        m.virtual_triangles,
        mb(m.many.peak_bytes),
        mb(m.one.peak_bytes),
        m.many.peak_bytes as f64 / m.one.peak_bytes as f64
    );
    let embree = m.embree.map_or("no Embree in this run".to_string(), |e| {
        format!(
            "Embree's harness (1 and 2 threads, one process) {:.1} MB",
            mb(e.peak_bytes)
        )
    });
    println!(
        "target: 1.1M-triangle bunny, peak memory <= Embree's: {:.1} MB on 1 thread, {:.1} MB on 2; {embree}",
        mb(m.big[0].peak_bytes),
        mb(m.big[1].peak_bytes)
    );
}

/// Where the 1,000 bunnies are written.
fn scene_path() -> PathBuf {
    crate::target_dir().join("bench/bunnies-1000.toml")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thousand_bunnies_share_one_mesh() {
        let root = crate::workspace_root();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bunnies.toml");
        std::fs::write(
            &path,
            bunnies(&root.join(super::super::scenes::BUNNY_OBJ)).unwrap(),
        )
        .unwrap();
        let file = scene_format::load_path(&path).unwrap_or_else(|e| panic!("{e}"));
        let scene = tracer_core::prepare(&file).unwrap();
        assert_eq!(scene.objects().len(), 1000);
        assert_eq!(scene.unique_primitives(), 69_666 + 1000);
    }
}
