//! The report: Markdown tables of the tracer's figures beside the peers'
//! from the same run, then the targets of `docs/src/performance.md`.

use super::stats::{median, spread};
use super::Row;

pub fn report(rows: &[Row], reps: usize) {
    println!(
        "Medians of {reps} runs, the scenes taking turns. Rays: primary (every sample's) + shadow + reflected.\n"
    );
    wall_times(rows);
    cpu_times(rows);
    loading(rows);
    embree(rows);
    println!();
    targets(rows);
}

fn wall_times(rows: &[Row]) {
    println!(
        "| scene | objects | BVH build 1 / 2 thr | render 1 thr | render 2 thr | Mrays/s 1 / 2 thr | 2-thr speed-up | POV-Ray 1 / 2 thr | POV-Ray / ours, 1 thr |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        let o = &r.ours;
        let (pov, ratio) = r.povray.map_or(("-".into(), "-".into()), |p| {
            (
                format!("{:.3} s / {:.3} s", p.wall_s[0], p.wall_s[1]),
                format!("{:.2}x", p.wall_s[0] / o.render_s[0]),
            )
        });
        println!(
            "| {} | {} | {:.3} s / {:.3} s | {:.3} s | {:.3} s | {:.2} / {:.2} | {:.2}x | {pov} | {ratio} |",
            r.scene,
            o.objects,
            o.build_s[0],
            o.build_s[1],
            o.render_s[0],
            o.render_s[1],
            o.mrays(0),
            o.mrays(1),
            median(o.speedup_runs.clone()),
        );
    }
}

fn cpu_times(rows: &[Row]) {
    println!("\nOne thread, CPU time of this process (less sensitive to other load):\n");
    println!("| scene | rays (nearest + shadow) | BVH build CPU | render CPU | Mrays per CPU-s | ns per ray | POV-Ray CPU | POV-Ray / ours, CPU | POV-Ray's rays (nearest + shadow) |");
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        let o = &r.ours;
        let (pov, ratio, pov_rays) = r.povray.map_or(("-".into(), "-".into(), "-".into()), |p| {
            (
                format!("{:.3} s", p.cpu_s),
                format!("{:.2}x", p.cpu_s / o.render_cpu_s),
                format!("{} + {}", p.rays.nearest, p.rays.shadow),
            )
        });
        println!(
            "| {} | {} + {} | {:.3} s | {:.3} s | {:.2} | {:.1} | {pov} | {ratio} | {pov_rays} |",
            r.scene,
            o.rays.nearest,
            o.rays.shadow,
            o.build_cpu_s,
            o.render_cpu_s,
            o.mrays_per_cpu_s(),
            o.ns_per_ray(),
        );
    }
}

/// Reading the mesh file and building its tree, on one thread (issue 16's
/// loading targets: each under 0.3 s at 1.1M triangles).
fn loading(rows: &[Row]) {
    if rows.iter().all(|r| r.ours.load_s.is_none()) {
        return;
    }
    println!("\nLoading, 1 thread: reading the OBJ file, building the BVH (CPU), the tree's SAH cost (primitive tests per ray), Embree's build in the same run:\n");
    println!("| scene | triangles | OBJ read | BVH build CPU | SAH cost | Embree build |");
    println!("| --- | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        let Some(load_s) = r.ours.load_s else {
            continue;
        };
        let embree = r
            .embree
            .map_or("-".into(), |e| format!("{:.3} s", e.build_s[0]));
        println!(
            "| {} | {} | {load_s:.3} s | {:.3} s | {:.2} | {embree} |",
            r.scene, r.ours.objects, r.ours.build_cpu_s, r.ours.sah_cost
        );
    }
}

fn embree(rows: &[Row]) {
    if rows.iter().all(|r| r.embree.is_none()) {
        return;
    }
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
                r.ours.mrays(0) / e.mrays[0]
            );
        }
    }
}

/// The targets, each with this run's figure.
fn targets(rows: &[Row]) {
    issue_6_targets(rows);
    if let Some(aa) = rows.iter().find(|r| r.scene == "bunny-16spp") {
        supersampling_target(aa);
    }
    if let Some(small) = rows.iter().find(|r| r.scene == "reflectance2") {
        small_scene_target(small);
    }
}

/// Issue 16's small-scene goal: the render's rays per second on one
/// thread, and the whole `tracer render` process (start-up, parse, render,
/// encode, write).
fn small_scene_target(row: &Row) {
    let o = &row.ours;
    println!(
        "target: {}, 1 thread, >= 40 Mrays/s: {:.2} Mrays/s wall, {:.2} per CPU-s ({:.1} ns per ray)",
        row.scene,
        o.mrays(0),
        o.mrays_per_cpu_s(),
        o.ns_per_ray()
    );
    let ms = |s: f64| s * 1e3;
    match o.process {
        Some(p) => println!(
            "target: {}, whole `tracer render --threads 1` process < 30 ms: {:.1} ms wall ({:.1}-{:.1}), {:.1} ms CPU ({:.1}-{:.1}); medians of {} runs",
            row.scene,
            ms(p.wall_s),
            ms(p.wall_range.0),
            ms(p.wall_range.1),
            ms(p.cpu_s),
            ms(p.cpu_range.0),
            ms(p.cpu_range.1),
            p.spawns
        ),
        None => println!("target: {}, whole process < 30 ms: not timed", row.scene),
    }
}

fn issue_6_targets(rows: &[Row]) {
    let find = |name: &str| rows.iter().find(|r| r.scene == name);
    if let (Some(small), Some(big)) = (find("bunny"), find("bunny-1.1m")) {
        let ratios: Vec<f64> = big
            .ours
            .ns_per_ray_runs
            .iter()
            .zip(&small.ours.ns_per_ray_runs)
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
        let o = &big.ours;
        println!(
            "target: BVH build of {} triangles < 1 s: {:.3} s wall, {:.3} s CPU on 1 thread; {:.3} s on 2",
            o.objects, o.build_s[0], o.build_cpu_s, o.build_s[1]
        );
    }
    let Some(b) = find("bunny") else {
        return;
    };
    let o = &b.ours;
    let figures = format!(
        "{:.2} Mrays/s wall, {:.2} per CPU-s",
        o.mrays(0),
        o.mrays_per_cpu_s()
    );
    match b.embree {
        Some(e) => println!(
            "target: bunny, 1 thread, >= half of Embree's primary + shadow + shade throughput: {figures} = {:.2} of Embree's {:.2} (this run)",
            o.mrays(0) / e.mrays[0],
            e.mrays[0]
        ),
        None => println!(
            "target: bunny, 1 thread, >= half of Embree's primary + shadow + shade throughput: {figures}; no Embree figure in this run"
        ),
    }
    let embree = b.embree.map_or(String::new(), |e| {
        format!("; Embree's: {:.2}x", e.mrays[1] / e.mrays[0])
    });
    println!(
        "target: 2-thread speed-up >= 1.8x: {:.2}x (median of each run's; runs {}{embree})",
        median(o.speedup_runs.clone()),
        spread(&o.speedup_runs)
    );
    if let Some(p) = b.povray {
        println!(
            "target: bunny, 1 thread, >= 3x POV-Ray render-only: {:.2}x wall, {:.2}x CPU",
            p.wall_s[0] / o.render_s[0],
            p.cpu_s / o.render_cpu_s
        );
    }
}

/// The bunny at 16 samples per pixel, >= 5x POV-Ray's supersampling, with
/// each side's camera rays per pixel, as POV-Ray casts 17 where we cast 16
/// (see `povray::antialias`).
fn supersampling_target(row: &Row) {
    let o = &row.ours;
    let Some(p) = row.povray else {
        println!("target: bunny-16spp, 1 thread, >= 5x POV-Ray render-only: no POV-Ray figure in this run");
        return;
    };
    // The bunny has no mirror: its nearest-hit rays are camera rays.
    let pixels = (o.pixels as f64).max(1.0);
    println!(
        "target: bunny-16spp, 1 thread, >= 5x POV-Ray render-only (+A0.0 +AM1 +R4): {:.2}x wall, {:.2}x CPU; camera rays per pixel: ours {:.2}, POV-Ray's {:.2}",
        p.wall_s[0] / o.render_s[0],
        p.cpu_s / o.render_cpu_s,
        o.rays.nearest as f64 / pixels,
        p.rays.nearest as f64 / pixels,
    );
}
