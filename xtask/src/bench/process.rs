//! Timing the whole `tracer render` process on a small scene: start-up,
//! reading and checking the scene file, the render, encoding and writing
//! the PNG (issue 16: reflectance2 under 30 ms on one thread). For a scene
//! this small the render is only part of what a user waits for.

use super::rusage;
use super::stats::{median, range};
use anyhow::{bail, Context, Result};
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Spawns of the process per bench run: each takes tens of milliseconds,
/// so several, for a median that the machine's noise moves less.
pub const SPAWNS_PER_RUN: usize = 5;

/// One spawn's wall time and the CPU time (user + system) of the child.
#[derive(Debug, Clone, Copy)]
pub struct Spawn {
    pub wall_s: f64,
    pub cpu_s: f64,
}

/// The process's figures: medians over every spawn, and the range.
#[derive(Debug, Clone, Copy)]
pub struct Process {
    pub wall_s: f64,
    pub cpu_s: f64,
    pub wall_range: (f64, f64),
    pub cpu_range: (f64, f64),
    pub spawns: usize,
}

impl Process {
    pub fn of(spawns: &[Spawn]) -> Process {
        let wall: Vec<f64> = spawns.iter().map(|s| s.wall_s).collect();
        let cpu: Vec<f64> = spawns.iter().map(|s| s.cpu_s).collect();
        Process {
            wall_s: median(wall.clone()),
            cpu_s: median(cpu.clone()),
            wall_range: range(&wall),
            cpu_range: range(&cpu),
            spawns: spawns.len(),
        }
    }
}

/// CPU seconds of the children this process has waited for, all together.
fn children_cpu_time() -> f64 {
    rusage::cpu_seconds(&rusage::of(libc::RUSAGE_CHILDREN))
}

/// Runs `tracer render SCENE --threads 1 -q -o OUT.png` once.
pub fn spawn(tracer: &Path, scene: &Path, out: &Path) -> Result<Spawn> {
    let cpu = children_cpu_time();
    let start = Instant::now();
    let status = Command::new(tracer)
        .arg("render")
        .arg(scene)
        .args(["--threads", "1", "-q", "-o"])
        .arg(out)
        .status()
        .with_context(|| format!("cannot run {}", tracer.display()))?;
    let wall_s = start.elapsed().as_secs_f64();
    if !status.success() {
        bail!(
            "{} render {} failed ({status})",
            tracer.display(),
            scene.display()
        );
    }
    Ok(Spawn {
        wall_s,
        cpu_s: children_cpu_time() - cpu,
    })
}

/// What `command` printed on standard output, once it has succeeded;
/// `what` names it in the errors, which carry its standard error.
pub fn stdout_of(command: &mut Command, what: &str) -> Result<String> {
    let out = command.output().with_context(|| format!("run {what}"))?;
    if !out.status.success() {
        bail!("{what} failed: {}", String::from_utf8_lossy(&out.stderr));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_and_ranges_of_spawns() {
        let spawns = [(0.030, 0.020), (0.050, 0.021), (0.040, 0.025)]
            .map(|(wall_s, cpu_s)| Spawn { wall_s, cpu_s });
        let p = Process::of(&spawns);
        assert_eq!((p.wall_s, p.cpu_s), (0.040, 0.021));
        assert_eq!(p.wall_range, (0.030, 0.050));
        assert_eq!(p.cpu_range, (0.020, 0.025));
        assert_eq!(p.spawns, 3);
    }
}
