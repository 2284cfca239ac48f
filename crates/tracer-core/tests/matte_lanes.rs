//! Small matte scenes trace sixteen paths at a time
//! (`integrate::path::matte_lanes`): every pixel's value, and every ray count,
//! must be the one-path tracer's, bit for bit, on the Cornell box and on
//! random rooms of triangles with emitters facing either way, black
//! materials, point lights and every `max_depth`, and on closed rooms
//! whose walls shadow rays may skip.

mod common;

use glam::Vec3;
use scene_format::Format;
use std::ops::Range;
use std::path::Path;
use tracer_core::integrate::path::{traces_paths_in_lanes, PathTracer, PixelSum};
use tracer_core::{prepare, Scene};

fn scene_from(text: &str) -> Scene {
    let file = scene_format::load_str(text, Format::Toml, Path::new("lanes.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    prepare(&plain(file)).expect("prepare")
}

/// `file` with each path traced alone: no path reuse, one camera ray (which
/// path mode would take in these rooms lit by their lamps); a test that
/// shares paths asks for it.
fn plain(mut file: scene_format::SceneFile) -> scene_format::SceneFile {
    (file.render.path_reuse, file.render.camera_rays) = (Some(1), Some(1));
    file
}

/// How a test traces: which samples of each pixel, with which seed.
#[derive(Clone, Debug)]
struct Run {
    samples: Range<u32>,
    seed: u32,
}

/// The means of samples `run.samples` of `pixels`, and the tracer's ray
/// counts: one path at a time, pixel by pixel; or in lanes, each run of
/// neighbours in a row traced together (`PathTracer::add_row`, as renders
/// and the film trace them).
fn trace(scene: &Scene, pixels: &[(u32, u32)], run: &Run, alone: bool) -> (Vec<Vec3>, [u64; 3]) {
    let tracer = PathTracer::new(scene).with_seed(run.seed);
    let mut sums = vec![PixelSum::default(); pixels.len()];
    if alone {
        let mut tracer = tracer.one_at_a_time();
        for (&(i, j), sum) in pixels.iter().zip(&mut sums) {
            tracer.add_samples(i, j, run.samples.clone(), sum, || false);
        }
        return (sums.iter().map(PixelSum::mean).collect(), counts(&tracer));
    }
    let mut tracer = tracer.in_lanes();
    let mut first = 0;
    while first < pixels.len() {
        let (i0, j) = pixels[first];
        let mut end = first + 1;
        while end < pixels.len() && pixels[end] == (i0 + (end - first) as u32, j) {
            end += 1;
        }
        let xs = i0..i0 + (end - first) as u32;
        tracer.add_row((xs, j), run.samples.clone(), &mut sums[first..end], || {
            false
        });
        first = end;
    }
    (sums.iter().map(PixelSum::mean).collect(), counts(&tracer))
}

/// The ray counts of `tracer`: nearest hits, shadow rays, dropped samples.
fn counts(tracer: &PathTracer) -> [u64; 3] {
    let s = tracer.stats;
    [s.nearest, s.shadow, s.dropped]
}

/// Asserts that lanes and single paths agree bit for bit on `pixels`.
fn assert_same(scene: &Scene, pixels: &[(u32, u32)], run: &Run, what: &str) {
    assert!(traces_paths_in_lanes(scene), "{what}: not traced in lanes");
    let (lanes, lane_rays) = trace(scene, pixels, run, false);
    let (alone, alone_rays) = trace(scene, pixels, run, true);
    for ((a, b), p) in lanes.iter().zip(&alone).zip(pixels) {
        let bits = |v: &Vec3| v.to_array().map(f32::to_bits);
        assert_eq!(
            bits(a),
            bits(b),
            "{what}: pixel {p:?}: {a} in lanes, {b} alone"
        );
    }
    assert_eq!(lane_rays, alone_rays, "{what}: rays counted");
}

#[test]
fn the_cornell_box_in_lanes_is_the_one_path_tracers_bit_for_bit() {
    let file = plain(common::load(&common::scenes_dir().join("cornell-box.toml")));
    let scene = prepare(&file).expect("prepare");
    // Every 37th pixel (each traced alone in lanes: 20 paths, the last 4
    // as lanes free up), then every 23rd row whole (traced together): the
    // lamp, its edges, walls, boxes and the open front. (The tree searches
    // this scene: more than 8 blocks of triangles.)
    let mut pixels: Vec<(u32, u32)> = (0..256 * 256)
        .step_by(37)
        .map(|k| (k % 256, k / 256))
        .collect();
    pixels.extend(
        (0..256)
            .step_by(23)
            .flat_map(|j| (0..256).map(move |i| (i, j))),
    );
    let run = Run {
        samples: 0..20,
        seed: 0,
    };
    assert_same(&scene, &pixels, &run, "Cornell box");
    // A pass that starts mid-way, as the film's do, with another seed.
    let run = Run {
        samples: 5..40,
        seed: 3,
    };
    assert_same(&scene, &pixels, &run, "Cornell box, 5..40");
    // The film's first passes: fewer samples than lanes, a row's pixels
    // traced together.
    for samples in [0..1, 1..2, 2..4] {
        let run = Run { samples, seed: 0 };
        assert_same(&scene, &pixels, &run, &format!("Cornell box, {run:?}"));
    }
}

/// xorshift: reproducible numbers in [0, 1) without a dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    fn point(&mut self, size: f32) -> String {
        let mut c = || (self.next() * 2.0 - 1.0) * size;
        format!("[{}, {}, {}]", c(), c(), c())
    }
}

/// A room of random triangles and quads around the camera: some
/// emissive (facing either way), some black, some sharing a vertex or
/// copied (ties in distance), now and then a point light, a background.
fn random_room(rng: &mut Rng) -> String {
    let max_depth = (rng.next() * 9.0) as u32;
    let background = if rng.next() < 0.5 {
        "[0, 0, 0]"
    } else {
        "[0.2, 0.3, 0.4]"
    };
    let lens = if rng.next() < 0.3 {
        "aperture = 0.3\nfocus_distance = 2\n"
    } else {
        ""
    };
    let mut text = format!(
        "[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = 90\nwidth = 8\nheight = 8\n{lens}\
         [render]\nintegrator = \"path\"\nmax_depth = {max_depth}\nbackground = {background}\n\
         [materials.white]\ndiffuse = [0.8, 0.8, 0.8]\n\
         [materials.red]\ndiffuse = [0.9, 0.2, 0.1]\n\
         [materials.black]\ndiffuse = [0, 0, 0]\n\
         [materials.bright]\ndiffuse = [1.5, 1, 0.5]\n\
         [materials.lamp]\ndiffuse = [0.5, 0.5, 0.5]\nemission = [4, 3, 2]\n\
         [materials.dark_lamp]\nemission = [2, 2, 6]\n"
    );
    if rng.next() < 0.3 {
        text += &format!(
            "[[lights]]\nposition = {}\ncolor = [3, 3, 3]\n",
            rng.point(2.0)
        );
    }
    let materials = ["white", "red", "black", "bright", "lamp", "dark_lamp"];
    let mut last = rng.point(3.0);
    // Up to 20 shapes, each copied at most once, but no more than 40
    // triangles: more than 32 make the tree search the scene.
    let shapes = 4 + (rng.next() * 17.0) as usize;
    let mut triangles = 0;
    for _ in 0..shapes {
        let material = materials[(rng.next() * materials.len() as f32) as usize];
        let shape = if rng.next() < 0.5 {
            // Sharing a vertex with the last one now and then.
            let v0 = if rng.next() < 0.3 {
                last.clone()
            } else {
                rng.point(3.0)
            };
            last = rng.point(3.0);
            format!("triangle = [{v0}, {last}, {}]", rng.point(3.0))
        } else {
            let (c, u, v) = (rng.point(3.0), rng.point(2.0), rng.point(2.0));
            format!("quad = {{ corner = {c}, edge_u = {u}, edge_v = {v} }}")
        };
        let copies = if rng.next() < 0.15 { 2 } else { 1 };
        let each = if shape.starts_with("quad") { 2 } else { 1 };
        if triangles + copies * each > 40 {
            break;
        }
        triangles += copies * each;
        for _ in 0..copies {
            text += &format!("[[objects]]\n{shape}\nmaterial = \"{material}\"\n");
        }
    }
    text
}

#[test]
fn random_matte_rooms_in_lanes_are_the_one_path_tracers_bit_for_bit() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let pixels: Vec<(u32, u32)> = (0..64).map(|k| (k % 8, k / 8)).collect();
    let mut searched_by_tree = 0;
    for room in 0..60 {
        let text = random_room(&mut rng);
        let scene = scene_from(&text);
        searched_by_tree += usize::from(scene.searches_together());
        let start = (rng.next() * 20.0) as u32;
        let run = Run {
            samples: start..start + 1 + (rng.next() * 45.0) as u32,
            seed: (rng.next() * 4.0) as u32,
        };
        assert_same(
            &scene,
            &pixels,
            &run,
            &format!("room {room}, {run:?}:\n{text}"),
        );
    }
    assert!(
        searched_by_tree >= 10,
        "{searched_by_tree} rooms searched by the tree"
    );
}

/// A closed room of five walls, two turned boxes standing on (or sunk
/// into) the floor and a lamp under the ceiling or a point light, each at
/// random distances from the walls, down to nearly touching one: the
/// walls the shadow rays skip (`casters.rs`), and those they must not.
fn random_closed_room(rng: &mut Rng) -> String {
    let max_depth = 1 + (rng.next() * 8.0) as u32;
    let gap = [0.0005, 0.005, 0.05, 0.3][(rng.next() * 4.0) as usize];
    let mut text = format!(
        "[camera]\neye = [0, 0, 0.95]\nlook_at = [0, 0, 0]\nfov = 80\nwidth = 8\nheight = 8\n\
         [render]\nintegrator = \"path\"\nmax_depth = {max_depth}\n\
         [materials.white]\ndiffuse = [0.8, 0.7, 0.6]\n\
         [materials.red]\ndiffuse = [0.9, 0.1, 0.1]\n\
         [materials.lamp]\ndiffuse = [0.8, 0.7, 0.6]\nemission = [9, 7, 4]\n"
    );
    let walls = [
        ([-1, -1, 1], [2, 0, 0], [0, 0, -2]),
        ([-1, 1, -1], [2, 0, 0], [0, 0, 2]),
        ([-1, -1, -1], [2, 0, 0], [0, 2, 0]),
        ([1, -1, -1], [0, 0, 2], [0, 2, 0]),
        ([-1, -1, 1], [0, 0, -2], [0, 2, 0]),
    ];
    for (c, u, v) in walls {
        let material = if c[0] == 1 { "red" } else { "white" };
        text += &format!(
            "[[objects]]\nquad = {{ corner = {c:?}, edge_u = {u:?}, edge_v = {v:?} }}\nmaterial = \"{material}\"\n"
        );
    }
    for _ in 0..2 {
        let (sx, sy, sz) = (
            0.1 + rng.next() * 0.3,
            0.1 + rng.next() * 0.5,
            0.1 + rng.next() * 0.3,
        );
        // Standing on the floor, or sunk a little into it.
        let y = -1.0 + sy - [0.0, 0.0, 0.01][(rng.next() * 3.0) as usize];
        let (x, z) = (rng.next() * 1.2 - 0.6, rng.next() * 1.2 - 0.6);
        let turn = rng.next() * 90.0;
        text += &format!(
            "[[objects]]\nbox = {{ min = [-1, -1, -1], max = [1, 1, 1] }}\n\
             transform = {{ scale = [{sx}, {sy}, {sz}], rotate = [0, {turn}, 0], translate = [{x}, {y}, {z}] }}\n\
             material = \"white\"\n"
        );
    }
    if rng.next() < 0.5 {
        let (x, z) = (rng.next() * 1.2 - 0.9, rng.next() * 1.2 - 0.9);
        text += &format!(
            "[[objects]]\nquad = {{ corner = [{x}, {}, {z}], edge_u = [0.4, 0, 0], edge_v = [0, 0, 0.3] }}\n\
             material = \"lamp\"\n",
            1.0 - gap
        );
    } else {
        // Near a side wall, the floor or the middle.
        let near = 1.0 - gap;
        let position = match (rng.next() * 3.0) as u32 {
            0 => format!("[{near}, 0.2, -0.3]"),
            1 => format!("[0.1, {}, 0.2]", -near),
            _ => "[0, 0.5, 0]".to_string(),
        };
        text += &format!("[[lights]]\nposition = {position}\ncolor = [2, 2, 2]\n");
    }
    text
}

#[test]
fn closed_rooms_in_lanes_are_the_one_path_tracers_bit_for_bit() {
    let mut rng = Rng(0xD1B5_4A32_D192_ED03);
    let pixels: Vec<(u32, u32)> = (0..64).map(|k| (k % 8, k / 8)).collect();
    for room in 0..40 {
        let text = random_closed_room(&mut rng);
        let scene = scene_from(&text);
        let run = Run {
            samples: 0..1 + (rng.next() * 40.0) as u32,
            seed: (rng.next() * 4.0) as u32,
        };
        assert_same(
            &scene,
            &pixels,
            &run,
            &format!("closed room {room}, {run:?}:\n{text}"),
        );
    }
}

#[test]
fn only_small_matte_scenes_go_in_lanes() {
    let room = "[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, -1]\nwidth = 4\nheight = 4\n\
                [render]\nintegrator = \"path\"\n\
                [materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n";
    let quad = "[[objects]]\nquad = { corner = [-1, -1, -2], edge_u = [2, 0, 0], edge_v = [0, 2, 0] }\nmaterial = \"m\"\n";
    assert!(traces_paths_in_lanes(&scene_from(&format!("{room}{quad}"))));
    let whitted = room.replace("integrator = \"path\"", "integrator = \"whitted\"");
    assert!(!traces_paths_in_lanes(&scene_from(&format!(
        "{whitted}{quad}"
    ))));
    for (what, extra) in [
        (
            "a highlight",
            "[materials.s]\nspecular = [0.5, 0.5, 0.5]\nshininess = 20\n",
        ),
        ("a mirror", "[materials.s]\nreflectance = 0.5\n"),
        ("glass", "[materials.s]\ntransmittance = 1\n"),
        (
            "a sphere light",
            "[[lights]]\nposition = [0, 1, -1]\ncolor = [1, 1, 1]\nradius = 0.1\n",
        ),
        (
            "a sphere",
            "[[objects]]\nsphere = { center = [0, 0, -3], radius = 0.5 }\nmaterial = \"m\"\n",
        ),
    ] {
        let text = format!("{room}{quad}{extra}");
        let used = extra.starts_with("[materials.s]");
        let text = if used {
            text.replace("material = \"m\"", "material = \"s\"")
        } else {
            text
        };
        assert!(!traces_paths_in_lanes(&scene_from(&text)), "{what}");
    }
    let many: String = (0..70).map(|_| quad).collect();
    assert!(
        !traces_paths_in_lanes(&scene_from(&format!("{room}{many}"))),
        "140 triangles"
    );
}

#[test]
fn lanes_read_the_background_the_scene_has_now() {
    let text = "[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, -1]\nwidth = 4\nheight = 4\n\
                [render]\nintegrator = \"path\"\n\
                [materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n\
                [[objects]]\nquad = { corner = [-0.2, -0.2, -2], edge_u = [0.4, 0, 0], edge_v = [0, 0.4, 0] }\nmaterial = \"m\"\n";
    let scene = scene_from(text);
    let mut trace_settings = scene.trace_settings().clone();
    trace_settings.background = Vec3::ONE;
    let scene = scene.with_trace_settings(trace_settings);
    let pixels: Vec<(u32, u32)> = (0..16).map(|k| (k % 4, k / 4)).collect();
    let run = Run {
        samples: 0..32,
        seed: 0,
    };
    assert_same(&scene, &pixels, &run, "a white background set after");
    let (values, _) = trace(&scene, &pixels, &run, false);
    assert!(values.contains(&Vec3::ONE), "the sky is white: {values:?}");
}

#[test]
fn with_path_reuse_lanes_and_single_paths_agree() {
    // Groups of 8 pixels sharing their paths' first bounces: the paths and
    // what they share are the same bit for bit; only the connections'
    // shadow rays are tested otherwise (against the triangles a segment
    // inside the room can meet, in lanes; the tree, alone), which may
    // rarely differ where a connection grazes a surface. 24 rows of 48.
    let path = common::scenes_dir().join("cornell-box.toml");
    let mut file = plain(common::load(&path));
    (file.camera.width, file.camera.height) = (48, 24);
    let scene = prepare(&file).expect("prepare");
    let image = |tracer: PathTracer| {
        let mut tracer = tracer.with_reuse(8);
        (0..24)
            .flat_map(|j| {
                let mut sums = vec![PixelSum::default(); 48];
                tracer.add_row((0..48, j), 0..16, &mut sums, || false);
                sums.iter().map(PixelSum::mean).collect::<Vec<_>>()
            })
            .collect::<Vec<_>>()
    };
    let lanes = image(PathTracer::new(&scene).in_lanes());
    let alone = image(PathTracer::new(&scene).one_at_a_time());
    let apart = lanes
        .iter()
        .zip(&alone)
        .filter(|(a, b)| (**a - **b).abs().max_element() > 1e-6 * b.max_element().max(1.0))
        .count();
    assert!(apart <= lanes.len() / 100, "{apart} pixels differ");
    // And sharing is on: the image is not that of paths alone.
    let plain = |tracer: PathTracer| {
        let mut sums = vec![PixelSum::default(); 48];
        tracer
            .one_at_a_time()
            .add_row((0..48, 5), 0..16, &mut sums, || false);
        sums.iter().map(PixelSum::mean).collect::<Vec<_>>()
    };
    assert_ne!(plain(PathTracer::new(&scene)), alone[5 * 48..6 * 48]);
}
