//! Issue 16's packet goal: the bunny's primary rays at 16 samples per
//! pixel, on one thread. Ours: the same rays stored, as the peer's harness
//! holds them, traced a pixel's 16 at a time (`Scene::closest_hits`); and,
//! for what making the rays adds, the render's distance output. Embree's
//! harness: `rtcIntersect1`, `rtcIntersect8` and `rtcIntersect16` over the
//! same rays, read from a file we write (a pixel's 16 in a row: an 8-ray
//! packet is half a pixel's samples, a 16-ray packet all of them).

use super::measure;
use anyhow::{Context, Result};
use scene_format::SceneFile;
use std::path::Path;
use std::process::Command;

/// The `--only` name of this measurement.
pub const PACKETS: &str = "packets";

/// Samples per pixel of the measurement.
const SAMPLES: u32 = 16;

/// The figures: ours, and Embree's Mrays/s with rtcIntersect1, 8 and 16
/// (when its harness ran).
pub struct Packets {
    ours: measure::PrimaryRays,
    embree: Option<([f64; 3], u64)>,
}

/// Measures ours on `bunny` and Embree's harness `embree` on `obj` (the
/// bunny's mesh), `reps` times each; the rays' file is written in `dir`.
pub fn measure(
    bunny: &SceneFile,
    obj: &Path,
    embree: Option<&Path>,
    reps: usize,
    dir: &Path,
) -> Result<Packets> {
    eprintln!("bench: primary rays at {SAMPLES} samples per pixel ...");
    let rays_file = dir.join("bunny-16spp.rays");
    let ours = measure::primary_rays(bunny, SAMPLES, reps, &rays_file)?;
    let embree = match embree {
        Some(exe) => {
            eprintln!("bench: Embree on the same rays ...");
            let text = super::process::stdout_of(
                Command::new(exe)
                    .arg(obj)
                    .arg("--rays")
                    .arg(&rays_file)
                    .args(["--reps", &reps.to_string()]),
                "embree_bench --rays",
            )?;
            Some(parse(&text).with_context(|| format!("unexpected embree_bench output:\n{text}"))?)
        }
        None => None,
    };
    std::fs::remove_file(&rays_file)?;
    Ok(Packets { ours, embree })
}

/// Embree's Mrays/s with rtcIntersect1, 8 and 16, and how many rays hit
/// (rtcIntersect1's count), from its `--rays` report.
fn parse(text: &str) -> Option<([f64; 3], u64)> {
    let line = |kernel: &str| {
        text.lines()
            .find(|l| l.trim_start().starts_with(&format!("rays {kernel} ")))
    };
    let mrays = |kernel: &str| -> Option<f64> {
        let before = line(kernel)?.split("Mrays/s").next()?;
        before.split_whitespace().last()?.parse().ok()
    };
    let hits = line("rtcIntersect1")?.split("(hits ").nth(1)?;
    Some((
        [
            mrays("rtcIntersect1")?,
            mrays("rtcIntersect8")?,
            mrays("rtcIntersect16")?,
        ],
        hits.split_whitespace().next()?.parse().ok()?,
    ))
}

pub fn report(p: &Packets) {
    let o = &p.ours;
    let mrays = |seconds: f64| o.rays as f64 / seconds / 1e6;
    let (stored, rendered) = (mrays(o.stored_s), mrays(o.render_s));
    println!(
        "\nPrimary rays at {SAMPLES} samples per pixel, 1 thread, the same {} rays (the bunny, nearest hits only):\n",
        o.rays
    );
    println!("| tracer | Mrays/s | ours (stored) / it |\n| --- | ---: | ---: |");
    println!("| ours: the rays stored, a pixel's {SAMPLES} together | {stored:.2} | |");
    println!("| ours: the render's distance output, the rays made as it goes | {rendered:.2} | |");
    let Some((embree, embree_hits)) = p.embree else {
        println!("\ntarget: primary rays at {SAMPLES} spp >= Embree's rtcIntersect8: {stored:.2} Mrays/s; no Embree figure in this run");
        return;
    };
    let kernels = [
        "rtcIntersect1",
        "rtcIntersect8 (8 of a pixel's samples)",
        "rtcIntersect16 (a pixel's 16)",
    ];
    for (kernel, theirs) in kernels.iter().zip(embree) {
        println!("| Embree {kernel} | {theirs:.2} | {:.2} |", stored / theirs);
    }
    println!("\nRays that hit: ours {}, Embree's {embree_hits}.", o.hits);
    println!(
        "\ntarget: primary rays at {SAMPLES} spp, 1 thread, >= Embree's rtcIntersect8 on the same rays: {stored:.2} Mrays/s = {:.2} of Embree's {:.2} (this run; the render's own {rendered:.2} = {:.2})",
        stored / embree[1],
        embree[1],
        rendered / embree[1]
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embree_packet_figures_are_read_from_its_report() {
        let text = "[rays 33177600 from x.rays, quality=medium threads=1]\n\
            \x20 rays rtcIntersect1                  2300.00 ms/frame     14.43 Mrays/s  (hits 1 of 2)\n\
            \x20 rays rtcIntersect8 (8 in a row)     1200.00 ms/frame     27.65 Mrays/s  (hits 1 of 2)\n\
            \x20 rays rtcIntersect16 (16 in a row)   1000.00 ms/frame     33.18 Mrays/s  (hits 1 of 2)\n";
        assert_eq!(parse(text), Some(([14.43, 27.65, 33.18], 1)));
        assert_eq!(
            parse("  rays rtcIntersect1  1 ms/frame  2.5 Mrays/s  (hits 1 of 2)"),
            None
        );
    }
}
