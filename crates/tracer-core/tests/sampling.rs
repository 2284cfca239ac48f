//! Anti-aliasing, soft shadows, depth of field and handedness, each checked
//! against geometry worked out by hand: similar triangles for a penumbra,
//! the thin lens' circle of confusion, the convergence rate of stratified
//! sampling, and mirror images.

mod common;

use common::on_threads;
use scene_format::Format;
use std::path::Path;
use tracer_core::integrate::whitted::Whitted;
use tracer_core::{prepare, render, LinearImage, Output, Region, RenderJob, Scene};

fn scene_from(text: &str) -> Scene {
    let file = scene_format::load_str(text, Format::Toml, Path::new("t.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    prepare(&file).expect("prepare")
}

fn render_region(scene: &Scene, region: Region, samples: u32) -> LinearImage {
    let job = RenderJob {
        region,
        samples,
        output: Output::Shading,
    };
    render(scene, &job, &|_| {}).image
}

/// The fraction of a unit disk on the far side of a chord at signed
/// distance `u` from its centre: (acos u - u sqrt(1 - u^2)) / pi.
fn disk_beyond(u: f64) -> f64 {
    let u = u.clamp(-1.0, 1.0);
    (u.acos() - u * (1.0 - u * u).sqrt()) / std::f64::consts::PI
}

/// Where the chord leaves `fraction` of the disk beyond it (bisection;
/// `disk_beyond` falls from 1 at -1 to 0 at 1).
fn chord_at(fraction: f64) -> f64 {
    let (mut lo, mut hi) = (-1.0, 1.0);
    for _ in 0..60 {
        let mid = (lo + hi) / 2.0;
        if disk_beyond(mid) > fraction {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo + hi) / 2.0
}

/// Where a profile sampled at `xs` first crosses `level`, linearly
/// interpolated between the two samples around the crossing.
fn crossing(xs: &[f64], values: &[f64], level: f64) -> f64 {
    let k = values
        .windows(2)
        .position(|w| (w[0] - level) * (w[1] - level) <= 0.0 && w[0] != w[1])
        .unwrap_or_else(|| panic!("the profile never crosses {level}"));
    let t = (level - values[k]) / (values[k + 1] - values[k]);
    xs[k] + t * (xs[k + 1] - xs[k])
}

// --- 1. Soft shadows: the penumbra of a straight edge ----------------------

/// Light: a sphere of radius R_LIGHT centred at height H_LIGHT above the
/// floor z = 0, over x = 0. Occluder: the half-plane x < 0 at height
/// H_OCC. Floor and occluder are large single triangles (no diagonal for a
/// shadow ray to slip through).
const R_LIGHT: f64 = 1.0;
const H_LIGHT: f64 = 10.0;
const H_OCC: f64 = 5.0;

/// The camera looks straight down from (EYE_X, 0, EYE_Z), so the floor is
/// parallel to the image plane and every pixel spans the same length of
/// floor. It sits over the lit side, high enough that its rays to the
/// penumbra pass beside the occluder: the ray to x = -1.5 crosses
/// z = 5 at x = -1.5 + 7.5 * 5/20 > 0.
const EYE_X: f64 = 6.0;
const EYE_Z: f64 = 20.0;
const FOV: f64 = 50.0;
const WIDTH: u32 = 1600;

fn penumbra_scene(occluder: bool, light_samples: u32) -> Scene {
    let occ = if occluder {
        format!(
            "[[objects]]\ntriangle = [[0, -100, {H_OCC}], [0, 100, {H_OCC}], [-100, 0, {H_OCC}]]\n\
             material = {{ diffuse = [0, 0, 0] }}\n"
        )
    } else {
        String::new()
    };
    scene_from(&format!(
        "[camera]\neye = [{EYE_X}, 0, {EYE_Z}]\nlook_at = [{EYE_X}, 0, 0]\n\
         fov = {FOV}\nwidth = {WIDTH}\nheight = 1\n\
         [render]\ngamma = 1\nlight_samples = {light_samples}\n\
         [[lights]]\nposition = [0, 0, {H_LIGHT}]\nradius = {R_LIGHT}\n\
         [[objects]]\ntriangle = [[-100, -100, 0], [100, -100, 0], [0, 100, 0]]\n\
         material = {{ diffuse = [1, 1, 1] }}\n{occ}"
    ))
}

/// The floor's x under the centre of column `i` (height 1: the row's
/// centre is the image's, y = 0). The lab's camera puts world +x on the
/// image's left, so x falls as i grows.
fn floor_x(i: u32) -> f64 {
    let focal = f64::from(WIDTH) / (2.0 * (FOV.to_radians() / 2.0).tan());
    EYE_X - (f64::from(i) + 0.5 - f64::from(WIDTH) / 2.0) * EYE_Z / focal
}

#[test]
fn a_sphere_lights_penumbra_spans_what_similar_triangles_predict() {
    // From a floor point at x, the occluder's edge hides the light's
    // points with x_L < -x (H - h) / h: lit throughout for x >= r h / (H - h),
    // dark for x <= -r h / (H - h), so the penumbra is w = 2 r h / (H - h).
    // This takes the light as a disk parallel to the floor; the renderer's
    // disk faces the shaded point instead, tilted by at most
    // atan(1 / 10) < 6 degrees across this penumbra, which moves the chord
    // the edge cuts by a factor cos 6 = 0.995, and the cosine of the floor
    // varies by under 2 % across the disk: well within the 10 %.
    let w = 2.0 * R_LIGHT * H_OCC / (H_LIGHT - H_OCC);
    // Between, the lit fraction is the disk's part beyond a chord at
    // u = -x (H - h) / (h r): 90 % and 10 % lie at u = -+u10, so the 10-90
    // width is 2 u10 r h / (H - h) = u10 w.
    let w_10_90 = chord_at(0.1) * w;

    // Columns over x in [-1.5, 1.5]; one ray through each pixel's centre.
    let (x0, x1) = (1180, 1450);
    let region = Region {
        x0,
        y0: 0,
        x1,
        y1: 1,
    };
    let light_samples = 1024;
    let shadowed = render_region(&penumbra_scene(true, light_samples), region, 1);
    let open = render_region(&penumbra_scene(false, light_samples), region, 1);
    // The same pixel without the occluder traces the same shadow rays (the
    // same seeds): the ratio is exactly 1 where none is blocked, and the
    // cosine's slow change along the floor divides out.
    let xs: Vec<f64> = (x0..x1).map(floor_x).collect();
    let lit: Vec<f64> = (0..x1 - x0)
        .map(|i| f64::from(shadowed.get(i, 0).x / open.get(i, 0).x))
        .collect();
    assert!(xs[0] > 1.4 && xs[xs.len() - 1] < -1.4, "{xs:?}");
    // x falls along the row: lit first, dark last. The penumbra's ends lie
    // between the last pixel of one kind and the first of the next.
    let first_partial = lit.iter().position(|&f| f != 1.0).unwrap();
    let first_dark = lit.iter().position(|&f| f == 0.0).unwrap();
    let full = (xs[first_partial - 1] + xs[first_partial]) / 2.0
        - (xs[first_dark - 1] + xs[first_dark]) / 2.0;
    let width_10_90 = crossing(&xs, &lit, 0.9) - crossing(&xs, &lit, 0.1);
    eprintln!(
        "penumbra: {full:.4} from lit to dark, predicted {w:.4}; \
         10-90 width {width_10_90:.4}, predicted {w_10_90:.4}"
    );
    assert!((full / w - 1.0).abs() < 0.1, "{full} vs {w}");
    assert!(
        (width_10_90 / w_10_90 - 1.0).abs() < 0.1,
        "{width_10_90} vs {w_10_90}"
    );
    // Half lit straight under the edge.
    let half = crossing(&xs, &lit, 0.5);
    assert!(half.abs() < 0.05 * w, "{half}");
}

// --- 2. Depth of field: the circle of confusion ----------------------------

/// The lab's camera at z = 10 looking down -z, focused on z = 0 (the
/// default focus distance, |look_at - eye|); a 200 x 200 image.
const FOCUS: f64 = 10.0;
const DOF_SIZE: u32 = 200;
const DOF_FOV: f64 = 50.0;

/// The camera's focal length in pixels: the lab's projection, whose fov is
/// horizontal.
fn dof_focal_px() -> f64 {
    f64::from(DOF_SIZE) / (2.0 * (DOF_FOV.to_radians() / 2.0).tan())
}

/// A lens of radius `aperture` and a half-plane at distance `d` from it,
/// facing it, with its edge through the view axis: x > 0 when
/// `vertical_edge`, else y > 0. Ambient 1 under a white light and a black
/// background: a ray that hits it brings back exactly 1, one that misses
/// 0, so a pixel is the fraction of its samples that hit.
fn edge_scene(aperture: f64, d: f64, vertical_edge: bool) -> Scene {
    let z = FOCUS - d;
    let triangle = if vertical_edge {
        format!("[[0, -100, {z}], [0, 100, {z}], [100, 0, {z}]]")
    } else {
        format!("[[-100, 0, {z}], [100, 0, {z}], [0, 100, {z}]]")
    };
    scene_from(&format!(
        "[camera]\neye = [0, 0, {FOCUS}]\nlook_at = [0, 0, 0]\n\
         fov = {DOF_FOV}\nwidth = {DOF_SIZE}\nheight = {DOF_SIZE}\naperture = {aperture}\n\
         [render]\ngamma = 1\n\
         [[lights]]\nposition = [0, 0, 20]\n\
         [[objects]]\ntriangle = {triangle}\nmaterial = {{ ambient = [1, 1, 1] }}\n"
    ))
}

/// The profile across the edge: row 100 for a vertical edge, column 100
/// for a horizontal one (the edge is the same all along it, so which row
/// does not matter).
fn edge_profile(aperture: f64, d: f64, vertical_edge: bool, samples: u32) -> Vec<f64> {
    let region = if vertical_edge {
        Region {
            x0: 0,
            y0: 100,
            x1: DOF_SIZE,
            y1: 101,
        }
    } else {
        Region {
            x0: 100,
            y0: 0,
            x1: 101,
            y1: DOF_SIZE,
        }
    };
    let scene = edge_scene(aperture, d, vertical_edge);
    let image = render_region(&scene, region, samples);
    image.pixels.iter().map(|p| f64::from(p.x)).collect()
}

#[test]
fn an_edge_off_the_focus_plane_blurs_over_the_circle_of_confusion() {
    let aperture = 1.0;
    let u10 = chord_at(0.1);
    // In front of the focus plane and behind it.
    for d in [5.0, 20.0] {
        // The rays from a point at distance d through the lens' rim meet
        // the focus plane on a circle of diameter 2 A |d - d_f| / d (similar
        // triangles with apex at the point); in pixels, times
        // focal_px / d_f.
        let coc = 2.0 * aperture * (d - FOCUS).abs() / d * dof_focal_px() / FOCUS;
        // Across the blur, a pixel sees the edge through the part of the
        // lens beyond a chord that sweeps the lens: the hit fraction falls
        // as `disk_beyond`, its 10-90 width is u10 * coc.
        let predicted = u10 * coc;
        for vertical_edge in [true, false] {
            let profile = edge_profile(aperture, d, vertical_edge, 1024);
            let xs: Vec<f64> = (0..profile.len()).map(|i| i as f64 + 0.5).collect();
            let width = (crossing(&xs, &profile, 0.1) - crossing(&xs, &profile, 0.9)).abs();
            // From all hit to all missed: the circle and the pixel's own width.
            let partial = profile.iter().filter(|&&f| f > 0.0 && f < 1.0).count() as f64;
            eprintln!(
                "d {d}, vertical edge {vertical_edge}: circle {coc:.2} px; \
                 10-90 width {width:.2} px, predicted {predicted:.2}; \
                 {partial} partly hit pixels, predicted {:.2}",
                coc + 1.0
            );
            assert!(
                (width / predicted - 1.0).abs() < 0.1,
                "d {d}: 10-90 width {width} px, predicted {predicted}"
            );
            assert!(
                (partial / (coc + 1.0) - 1.0).abs() < 0.1,
                "d {d}: {partial} partly hit pixels, predicted {}",
                coc + 1.0
            );
        }
    }
    // On the focus plane the edge stays sharp: it lies on the border of
    // columns (rows) 99 and 100, so no pixel is partly hit (one, allowing
    // for rounding at the border).
    for vertical_edge in [true, false] {
        let profile = edge_profile(aperture, FOCUS, vertical_edge, 1024);
        let partial = profile.iter().filter(|&&f| f > 0.0 && f < 1.0).count();
        assert!(partial <= 1, "{partial} partly hit pixels in focus");
    }
}

/// A pixel straddling the edge of a blur about a pixel wide, averaged over
/// its samples and over 64 rows (each its own seeds, the same edge): it
/// must be the mean over the pixel of the lens' hit fraction. This is where
/// the pixel's and the lens' strata both matter, so where pairing them the
/// same way in every pixel would show as a bias that no sample count
/// removes.
#[test]
fn a_blur_about_a_pixel_wide_averages_the_lens_over_the_pixel() {
    let rows = 64;
    // Blur radii (half the circle) of -1.07 px (in front: the image
    // through the lens' +u side moves to -u) and 2.14 px (behind).
    for (aperture, d) in [(0.05, 5.0), (0.2, 20.0)] {
        let half_coc = aperture * (d - FOCUS) * dof_focal_px() / (d * FOCUS);
        let scene = edge_scene(aperture, d, true);
        let region = Region {
            x0: 90,
            y0: 100 - rows / 2,
            x1: 110,
            y1: 100 + rows / 2,
        };
        let image = render_region(&scene, region, 256);
        for i in 0..image.width {
            let got =
                (0..rows).map(|j| f64::from(image.get(i, j).x)).sum::<f64>() / f64::from(rows);
            // Column 90 + i spans image x in [90 + i, 91 + i); the edge's
            // sharp image is x = 100 and x < 100 sees the half-plane. From
            // image point x, a lens point at u-offset a (in radii) hits when
            // x - 100 < a half_coc: the disk's part beyond a chord at
            // (x - 100) / |half_coc|, whichever the sign.
            let m = 4000;
            let expected = (0..m)
                .map(|q| {
                    let x = f64::from(90 + i) + (f64::from(q) + 0.5) / f64::from(m);
                    disk_beyond((x - 100.0) / half_coc.abs())
                })
                .sum::<f64>()
                / f64::from(m);
            assert!(
                (got - expected).abs() < 0.01,
                "blur radius {half_coc:.2} px, column {}: {got:.4}, expected {expected:.4}",
                90 + i
            );
        }
    }
}

// --- 3. Convergence --------------------------------------------------------

/// Flat-coloured spheres and triangles at depths 8 to 16 from the eye:
/// ambient only, so within an object the colour is constant and all the
/// error of a pixel comes from the edges it holds (or, with a lens, from
/// the blur it lies in). 48 x 48 pixels.
fn edges_scene(aperture: f64) -> Scene {
    scene_from(&format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 48\nheight = 48\n\
         aperture = {aperture}\n\
         [render]\ngamma = 1\n\
         [[lights]]\nposition = [0, 0, 20]\n\
         [[objects]]\nsphere = {{ center = [-1.2, 0.8, 2], radius = 0.9 }}\n\
         material = {{ ambient = [1, 0.2, 0.1] }}\n\
         [[objects]]\nsphere = {{ center = [1.0, -0.6, -2], radius = 1.3 }}\n\
         material = {{ ambient = [0.1, 0.9, 0.3] }}\n\
         [[objects]]\nsphere = {{ center = [0.3, 1.4, 0], radius = 0.4 }}\n\
         material = {{ ambient = [0.2, 0.3, 1] }}\n\
         [[objects]]\ntriangle = [[-2.5, -2.5, 1], [0.5, -2.0, 1], [-1.0, 0.2, 1]]\n\
         material = {{ ambient = [0.9, 0.9, 0.2] }}\n\
         [[objects]]\ntriangle = [[-8, -8, -6], [8, -8, -6], [8, 8, -6]]\n\
         material = {{ ambient = [0.3, 0.3, 0.3] }}\n"
    ))
}

fn rms(a: &LinearImage, b: &LinearImage) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| f64::from((*p - *q).length_squared()))
        .sum();
    (sum / a.pixels.len() as f64).sqrt()
}

/// The RMS error at 4, 16 and 64 samples against 1,024, and each step's
/// ratio, which must be at most `bound`; N^-1/2 would be 0.5 a step.
fn assert_converges(what: &str, render_at: &dyn Fn(u32) -> LinearImage, bound: f64) {
    let reference = render_at(1024);
    let errors: Vec<f64> = [4, 16, 64]
        .iter()
        .map(|&n| rms(&render_at(n), &reference))
        .collect();
    let ratios = [errors[1] / errors[0], errors[2] / errors[1]];
    eprintln!("{what}: RMS errors at 4, 16, 64: {errors:.4?}, ratios {ratios:.3?}");
    assert!(ratios.iter().all(|&r| r <= bound), "{what}: {errors:?}");
}

/// Stratified jittered samples of an edge: the error comes from the
/// ~sqrt(N) strata the edge crosses, each off by at most 1/N, so the
/// variance falls as N^-3/2 and the RMS error by 4^-3/4 = 0.35 per step;
/// N^-1/2 (0.5) with no slack still leaves 40 % for the noise of an RMS
/// over a few hundred edge pixels (the ratios vary by about 10 % when the
/// scene moves a little).
const STRATIFIED_BOUND: f64 = 0.5;

#[test]
fn anti_aliasing_converges_faster_than_one_over_root_n() {
    let scene = edges_scene(0.0);
    let whole = Region::full(48, 48);
    assert_converges(
        "anti-aliasing",
        &|n| render_region(&scene, whole, n),
        STRATIFIED_BOUND,
    );
}

#[test]
fn depth_of_field_converges_as_one_over_root_n() {
    // Blur circles of 0.8 to 2.5 px: pixel and lens matter alike. Each is
    // stratified on its own, but they are paired at random, and what
    // depends on both converges as for independent samples, N^-1/2: the
    // ratio is about 0.5 (0.42 to 0.53 as the eye moves by a tenth), so
    // 20 % slack for the noise. A pairing shared by every pixel (the bug
    // this caught) gave 0.86 from 16 to 64 samples here.
    let scene = edges_scene(0.5);
    let whole = Region::full(48, 48);
    assert_converges(
        "depth of field",
        &|n| render_region(&scene, whole, n),
        0.5 * 1.2,
    );
}

#[test]
fn soft_shadows_converge_faster_than_one_over_root_n() {
    // A sphere's shadow under a sphere light, from straight above: a ring
    // of penumbra around the umbra (radii about 0.75 and 2.25 on the
    // floor). One ray per pixel centre; light_samples varies. The shadow
    // rays are stratified over the light's disk, whose visible part ends at
    // an edge: the same N^-3/4 as anti-aliasing.
    let scene = scene_from(
        "[camera]\neye = [0, 0, 20]\nlook_at = [0, 0, 0]\nfov = 17\nwidth = 32\nheight = 32\n\
         [render]\ngamma = 1\n\
         [[lights]]\nposition = [0, 0, 6]\nradius = 1.5\n\
         [[objects]]\nsphere = { center = [0, 0, 2], radius = 1 }\n\
         material = { diffuse = [0, 0, 0] }\n\
         [[objects]]\ntriangle = [[-50, -50, 0], [50, -50, 0], [0, 50, 0]]\n\
         material = { diffuse = [1, 1, 1] }\n",
    );
    let whole = Region::full(32, 32);
    assert_converges(
        "soft shadows",
        &|n| {
            let mut trace = scene.trace_settings().clone();
            trace.light_samples = n;
            let scene = scene.clone().with_trace_settings(trace);
            render_region(&scene, whole, 1)
        },
        STRATIFIED_BOUND,
    );
}

// --- 4. The lab's image and determinism ------------------------------------

#[test]
fn one_sample_is_the_labs_ray_through_each_pixel_centre_on_any_thread_count() {
    // Shadows and a mirror: the lab's scenes with the most rays per pixel.
    for name in ["shadows", "reflectance2"] {
        let scene = prepare(&common::load(
            &common::scenes_dir().join(format!("{name}.toml")),
        ))
        .unwrap();
        assert_eq!(scene.samples(), 1);
        let job = RenderJob::full(&scene);
        let one = on_threads(1, || render(&scene, &job, &|_| {}).image);
        let three = on_threads(3, || render(&scene, &job, &|_| {}).image);
        assert!(one == three, "{name}: the image depends on the threads");
        // The lab's rayTrace of the primary ray through each pixel's centre,
        // traced here one by one.
        let mut tracer = Whitted::new(&scene);
        for j in 0..one.height {
            for i in 0..one.width {
                let ray = scene.camera().primary_ray(i, j);
                let expected = tracer.trace(&ray, 1.0, 0);
                assert_eq!(one.get(i, j), expected, "{name} ({i}, {j})");
            }
        }
    }
}

#[test]
fn sixteen_samples_with_a_lens_and_a_sphere_light_are_the_same_every_time() {
    // Every random number a render draws: pixel jitter, lens strata and
    // jitter, light strata and jitter, on a mirror's reflected rays too.
    let scene = scene_from(
        "[camera]\neye = [0, 1, 8]\nlook_at = [0, 0, 0]\nfov = 45\nwidth = 64\nheight = 48\n\
         aperture = 0.2\nfocus_distance = 7\n\
         [render]\nsamples = 16\nlight_samples = 8\nmax_depth = 2\n\
         [[lights]]\nposition = [2, 5, 4]\nradius = 0.8\n\
         [[objects]]\nsphere = { center = [-1, 0, 0], radius = 1 }\n\
         material = { diffuse = [0.2, 0.2, 0.2], reflectance = 0.8 }\n\
         [[objects]]\nsphere = { center = [1.2, -0.4, 1.5], radius = 0.6 }\n\
         material = { ambient = [0.1, 0, 0], diffuse = [0.8, 0.1, 0.1] }\n\
         [[objects]]\ntriangle = [[-20, -1, -20], [-20, -1, 20], [20, -1, 20]]\n\
         material = { diffuse = [0.7, 0.7, 0.7] }\n\
         [[objects]]\ntriangle = [[-20, -1, -20], [20, -1, 20], [20, -1, -20]]\n\
         material = { diffuse = [0.7, 0.7, 0.7] }\n",
    );
    let job = RenderJob::full(&scene);
    assert_eq!(job.samples, 16);
    let one = on_threads(1, || render(&scene, &job, &|_| {}).image);
    let three = on_threads(3, || render(&scene, &job, &|_| {}).image);
    let again = on_threads(3, || render(&scene, &job, &|_| {}).image);
    assert!(one == three, "the image depends on the threads");
    assert!(three == again, "the image differs between two runs");
    // Lit, and not the pinhole's one-sample image.
    assert!(one.pixels.iter().any(|p| p.x > 0.1));
    assert!(one != render(&scene, &job.with_samples(1), &|_| {}).image);
}

// --- 5. Handedness ---------------------------------------------------------

/// A red sphere at +x and a blue one at -x, lit from x = 0: a scene
/// symmetric in x but for the colours. `extra` goes in `[camera]`.
fn red_right_blue_left(handedness: &str, extra: &str, light_radius: f64) -> Scene {
    scene_from(&format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 80\nheight = 60\n\
         handedness = \"{handedness}\"\n{extra}\n\
         [render]\ngamma = 1\n\
         [[lights]]\nposition = [0, 4, 10]\nradius = {light_radius}\n\
         [[objects]]\nsphere = {{ center = [1.5, 0, 0], radius = 1 }}\n\
         material = {{ ambient = [0.1, 0, 0], diffuse = [0.8, 0, 0] }}\n\
         [[objects]]\nsphere = {{ center = [-1.5, 0, 0], radius = 1 }}\n\
         material = {{ ambient = [0, 0, 0.1], diffuse = [0, 0, 0.8] }}\n"
    ))
}

/// The mean column of the pixels where `channel` is lit.
fn mean_column(image: &LinearImage, channel: usize) -> f64 {
    let columns: Vec<f64> = (0..image.height)
        .flat_map(|j| (0..image.width).map(move |i| (i, j)))
        .filter(|&(i, j)| image.get(i, j)[channel] > 0.0)
        .map(|(i, _)| f64::from(i) + 0.5)
        .collect();
    assert!(!columns.is_empty());
    columns.iter().sum::<f64>() / columns.len() as f64
}

fn mirrored(image: &LinearImage) -> LinearImage {
    let mut out = LinearImage::new(image.width, image.height);
    for j in 0..image.height {
        for i in 0..image.width {
            out.pixels[(j * image.width + i) as usize] = image.get(image.width - 1 - i, j);
        }
    }
    out
}

#[test]
fn a_right_handed_camera_puts_plus_x_on_the_right_and_mirrors_the_labs_image() {
    let image = |handedness, extra, light_radius, samples| {
        let scene = red_right_blue_left(handedness, extra, light_radius);
        render_region(&scene, Region::full(80, 60), samples)
    };
    let lab = image("lab", "", 0.0, 1);
    let right = image("right", "", 0.0, 1);
    // The spheres' centres are 1.5 / 10 * focal = 12.9 px either side of
    // the middle (column 40).
    let focal = 80.0 / (2.0 * 25f64.to_radians().tan());
    let offset = 1.5 / 10.0 * focal;
    for (image, red_side) in [(&lab, -1.0), (&right, 1.0)] {
        let (red, blue) = (mean_column(image, 0), mean_column(image, 2));
        eprintln!("handedness: red at column {red:.2}, blue at {blue:.2}");
        assert!(
            (red - (40.0 + red_side * offset)).abs() < 1.0,
            "red at {red}"
        );
        assert!(
            (blue - (40.0 - red_side * offset)).abs() < 1.0,
            "blue at {blue}"
        );
    }
    // One ray per pixel centre: the right-handed rays are the lab's
    // mirrored, up to rounding (the corner ray o is computed another way),
    // so all but a few silhouette pixels match to float precision.
    let flipped = mirrored(&lab);
    let off = right
        .pixels
        .iter()
        .zip(&flipped.pixels)
        .filter(|(a, b)| (**a - **b).abs().max_element() > 1e-5)
        .count();
    eprintln!("handedness: {off} pixels of 4800 differ from the mirrored lab image");
    assert!(off <= 10, "{off} pixels differ from the mirror image");
    // With samples, a lens and a sphere light, a pixel and its mirror draw
    // other random numbers: equal within the 16-sample noise, far from the
    // unmirrored image.
    let extra = "aperture = 0.3\nfocus_distance = 9";
    let lab = image("lab", extra, 1.0, 16);
    let right = image("right", extra, 1.0, 16);
    let (to_mirror, unmirrored) = (rms(&right, &mirrored(&lab)), rms(&right, &lab));
    eprintln!("handedness at 16 samples: RMS {to_mirror:.4} to the mirror, {unmirrored:.4} to the lab image");
    assert!(to_mirror < 0.1 * unmirrored, "{to_mirror} vs {unmirrored}");
}
