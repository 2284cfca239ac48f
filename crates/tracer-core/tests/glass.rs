//! Glass in scenes: each test checks the tracer against optics worked out
//! by hand from the textbook formulas (Snell, Fresnel, Beer-Lambert, the
//! ball lens, the lab's Blinn-Phong), never against an earlier render.

use glam::{DVec3, Vec3};
use scene_format::Format;
use std::f64::consts::PI;
use std::path::Path;
use tracer_core::geometry::SurfaceHit;
use tracer_core::integrate::whitted::refracted_path;
use tracer_core::material::{Glass, Phong};
use tracer_core::{prepare, render, LinearImage, Ray, RenderJob, Scene, EPSILON};

fn scene_from(text: &str) -> Scene {
    let file = scene_format::load_str(text, Format::Toml, Path::new("glass.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    prepare(&file).expect("prepare")
}

fn render_image(scene: &Scene) -> LinearImage {
    render(scene, &RenderJob::full(scene), &|_| {}).image
}

/// A TOML array; `{:?}` prints the shortest text that reads back as the
/// same f32, so vertices are exactly what the test computed.
fn arr(p: Vec3) -> String {
    format!("[{:?}, {:?}, {:?}]", p.x, p.y, p.z)
}

/// `[[objects]]` triangles of material `material`, each ordered so that
/// its lab normal, normalize(cross(v1 - v0, v2 - v0)), points away from
/// `inside`: a closed convex solid whose normals face out, so a ray going
/// in meets front faces and a ray going out back faces.
fn solid(triangles: &[[Vec3; 3]], inside: Vec3, material: &str) -> String {
    let mut text = String::new();
    for &[a, b, c] in triangles {
        let centre = (a + b + c) / 3.0;
        let outward = (b - a).cross(c - a).dot(centre - inside) > 0.0;
        let [a, b, c] = if outward { [a, b, c] } else { [a, c, b] };
        text += &format!(
            "[[objects]]\ntriangle = [{}, {}, {}]\nmaterial = \"{material}\"\n",
            arr(a),
            arr(b),
            arr(c)
        );
    }
    text
}

/// A box centred on `centre` with orthonormal axes `axes` and half sizes
/// `half`: twelve triangles, normals out.
fn cuboid(centre: Vec3, axes: [Vec3; 3], half: [f32; 3], material: &str) -> String {
    let mut triangles = Vec::new();
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        for s in [-1.0, 1.0] {
            let face = centre + s * half[k] * axes[k];
            let corner = |a: f32, b: f32| face + a * half[i] * axes[i] + b * half[j] * axes[j];
            let [p00, p10, p11, p01] = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            triangles.push([p00, p10, p11]);
            triangles.push([p00, p11, p01]);
        }
    }
    solid(&triangles, centre, material)
}

/// A slab of `thickness` whose faces have normals +-`normal`, centred on
/// `centre`, 10 units wide: far wider than any ray here travels sideways,
/// and small enough that its f32 vertices put the faces where they belong
/// to ~1e-6.
fn slab(centre: Vec3, normal: Vec3, thickness: f32, material: &str) -> String {
    let [t1, t2] = tangents(normal);
    cuboid(
        centre,
        [normal, t1, t2],
        [thickness / 2.0, 5.0, 5.0],
        material,
    )
}

/// Two unit vectors across unit `n`, making a right-handed frame with it.
fn tangents(n: Vec3) -> [Vec3; 2] {
    let helper = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let t1 = n.cross(helper).normalize();
    [t1, n.cross(t1)]
}

/// A camera, a render section and one light, as TOML.
struct Setup<'a> {
    eye: Vec3,
    look_at: Vec3,
    up: Vec3,
    size: (u32, u32),
    max_depth: u32,
    min_energy: f32,
    background: Vec3,
    light: (Vec3, Vec3),
    materials: &'a str,
}

impl<'a> Setup<'a> {
    /// One ray, from `eye` toward `look_at`, deep enough for glass, over a
    /// black background, lit from above.
    fn one_ray(eye: Vec3, look_at: Vec3, materials: &'a str) -> Self {
        Setup {
            eye,
            look_at,
            up: Vec3::Y,
            size: (1, 1),
            max_depth: 8,
            min_energy: 0.01,
            background: Vec3::ZERO,
            light: (Vec3::new(0.0, 20.0, 0.0), Vec3::ONE),
            materials,
        }
    }

    fn toml(&self, objects: &str) -> String {
        format!(
            "[camera]\neye = {}\nlook_at = {}\nup = {}\nfov = 40\nwidth = {}\nheight = {}\n\
             [render]\nmax_depth = {}\nmin_energy = {:?}\nbackground = {}\ngamma = 1\n\
             [[lights]]\nposition = {}\ncolor = {}\n{}\n{objects}",
            arr(self.eye),
            arr(self.look_at),
            arr(self.up),
            self.size.0,
            self.size.1,
            self.max_depth,
            self.min_energy,
            arr(self.background),
            arr(self.light.0),
            arr(self.light.1),
            self.materials,
        )
    }
}

/// The textbook Fresnel reflectance of unpolarised light going from index
/// `n1` to `n2` at incidence angle `i` (radians): the mean of
/// ((n1 cos i - n2 cos t) / (n1 cos i + n2 cos t))^2 and
/// ((n1 cos t - n2 cos i) / (n1 cos t + n2 cos i))^2; 1 past the critical angle.
fn fresnel(n1: f64, n2: f64, i: f64) -> f64 {
    let sin_t = n1 / n2 * i.sin();
    if sin_t >= 1.0 {
        return 1.0;
    }
    let (ci, ct) = (i.cos(), sin_t.asin().cos());
    let rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
    let rp = (n1 * ct - n2 * ci) / (n1 * ct + n2 * ci);
    (rs * rs + rp * rp) / 2.0
}

fn close(a: Vec3, b: DVec3, tolerance: f64) -> bool {
    (a.as_dvec3() - b).abs().max_element() <= tolerance
}

// 1. A sphere of ior 1 and transmittance 1 with no colour of its own.

const INVISIBLE_MATERIALS: &str = r#"
[materials.floor]
ambient = [0.1, 0.1, 0.1]
diffuse = [0.6, 0.6, 0.6]
specular = [0.3, 0.3, 0.3]
shininess = 20

[materials.mirror]
ambient = [0.1, 0, 0]
diffuse = [0.5, 0.1, 0.1]
specular = [0.5, 0.5, 0.5]
shininess = 30
reflectance = 0.5

[materials.air]
transmittance = 1
ior = 1
"#;

/// A floor of two triangles, a mirror sphere, two lights with shadows;
/// with `air`, an invisible sphere in front of the mirror, over the floor
/// and in the way of a light (it would cast a shadow).
fn invisible_scene(air: bool) -> Scene {
    let floor = floor_square(20.0);
    // The floor is seen from above: its normals must point up.
    for [a, b, c] in floor {
        assert!((b - a).cross(c - a).y > 0.0);
    }
    let mut objects = String::new();
    for [a, b, c] in floor {
        objects += &format!(
            "[[objects]]\ntriangle = [{}, {}, {}]\nmaterial = \"floor\"\n",
            arr(a),
            arr(b),
            arr(c)
        );
    }
    objects +=
        "[[objects]]\nsphere = { center = [1.2, 0.8, -1], radius = 0.8 }\nmaterial = \"mirror\"\n";
    if air {
        objects += "[[objects]]\nsphere = { center = [-0.6, 0.9, 1.5], radius = 0.7 }\nmaterial = \"air\"\n";
    }
    let text = format!(
        "{}[[lights]]\nposition = [4, 5, 2]\ncolor = [0.4, 0.4, 0.4]\n",
        Setup {
            eye: Vec3::new(0.0, 2.0, 8.0),
            look_at: Vec3::new(0.0, 0.5, 0.0),
            up: Vec3::Y,
            size: (80, 60),
            // Each crossing of the invisible sphere spends a level of the
            // ray tree (in, out): a ray through it, off the mirror, and
            // through it again needs 2 + 1 + 2 = 5 levels to reach the
            // floor; 8 is enough, so no path is cut that the scene
            // without the sphere traces in full.
            max_depth: 8,
            min_energy: 0.01,
            background: Vec3::new(0.2, 0.3, 0.5),
            light: (Vec3::new(-3.0, 6.0, 5.0), Vec3::splat(0.6)),
            materials: INVISIBLE_MATERIALS,
        }
        .toml(&objects)
    );
    scene_from(&text)
}

/// Whether the segment from `a` to `b` passes through the ball of centre
/// `c` and radius `r` (the closest point of the segment lies inside).
fn segment_meets_ball(a: Vec3, b: Vec3, c: Vec3, r: f32) -> bool {
    let d = b - a;
    let s = ((c - a).dot(d) / d.dot(d)).clamp(0.0, 1.0);
    (a + s * d - c).length() < r
}

#[test]
fn a_sphere_of_air_is_invisible() {
    let scene = invisible_scene(true);
    // The sphere must be in the picture and in a light's way, or the test
    // shows nothing: count the pixels that see it, and those that see
    // floor it would shadow from the first light.
    let (centre, radius) = (Vec3::new(-0.6, 0.9, 1.5), 0.7);
    let camera = scene.camera();
    let (mut seen, mut shadowed) = (0, 0);
    for j in 0..camera.height {
        for i in 0..camera.width {
            let ray = camera.primary_ray(i, j);
            let to_centre = centre - ray.origin();
            let miss = (to_centre - to_centre.dot(ray.dir()) * ray.dir()).length();
            if miss < radius {
                seen += 1;
            } else if ray.dir().y < 0.0 {
                let floor = ray.at(-ray.origin().y / ray.dir().y);
                let light = Vec3::new(-3.0, 6.0, 5.0);
                if segment_meets_ball(floor, light, centre, radius) {
                    shadowed += 1;
                }
            }
        }
    }
    assert!(
        seen > 300 && shadowed > 100,
        "seen {seen}, shadowed {shadowed}"
    );

    let with = render_image(&scene);
    let without = render_image(&invisible_scene(false));
    // Not bit for bit: past the sphere a ray starts again at the point
    // where it left it, and `origin + t dir` rounds differently from the
    // same point reached from the eye, moving the hit by an ulp or so
    // (~1e-7 here, seen in 110 of the 4800 pixels). Shading is continuous
    // in the point, so the colours move by as little; 1e-5 is far below
    // any real effect of the sphere (an opaque one would shadow ~0.28 of
    // the floor's colour away).
    let worst = with
        .pixels
        .iter()
        .zip(&without.pixels)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0, f32::max);
    assert!(worst < 1e-5, "worst difference {worst}");
}

// 2. and 4. A slab, tilted so that no axis is special.

fn slab_normal() -> Vec3 {
    Vec3::new(1.0, 2.0, 0.5).normalize()
}

/// Only the slab, of `thickness` and index `ior`, centred on the origin.
fn slab_scene(ior: f32, thickness: f32) -> Scene {
    let materials = format!("[materials.glass]\ntransmittance = 1\nior = {ior:?}\n");
    scene_from(
        &Setup::one_ray(Vec3::new(0.0, 0.0, 20.0), Vec3::ZERO, &materials).toml(&slab(
            Vec3::ZERO,
            slab_normal(),
            thickness,
            "glass",
        )),
    )
}

/// A unit direction at `angle` (radians) from `axis`, tilted toward a
/// direction across it chosen so that it lies along neither tangent.
fn at_angle(axis: Vec3, angle: f64) -> (Vec3, Vec3) {
    let [t1, t2] = tangents(axis);
    let across = (t1 * 0.6 + t2 * 0.8).normalize();
    let dir = axis.as_dvec3() * angle.cos() + across.as_dvec3() * angle.sin();
    (dir.as_vec3().normalize(), across)
}

#[test]
fn a_slab_shifts_a_ray_sideways_by_the_textbook_amount_and_keeps_its_direction() {
    let (n, d) = (1.5f64, 0.5f64);
    let scene = slab_scene(n as f32, d as f32);
    let normal = slab_normal();
    for degrees in [0.0f64, 15.0, 30.0, 45.0, 60.0, 75.0] {
        let theta_i = degrees.to_radians();
        let (dir, across) = at_angle(-normal, theta_i);
        // Aim at a point of the upper face (normal +normal) off the centre.
        let entry = normal * (d as f32 / 2.0) + across * 0.3;
        let ray = Ray::new(entry - 3.0 * dir, dir);
        let path = refracted_path(&scene, &ray, 10);
        assert_eq!(path.len(), 3, "{degrees} deg: in, through, out");
        // Snell: sin(theta_r) = sin(theta_i) / n.
        let theta_r = (theta_i.sin() / n).asin();
        let inside = -normal.as_dvec3() * theta_r.cos() + across.as_dvec3() * theta_r.sin();
        assert!(
            close(path[1].dir(), inside, 1e-5),
            "{degrees}: {}",
            path[1].dir()
        );
        // The exit point, d tan(theta_r) along the face from the entry.
        let exit = entry.as_dvec3() - normal.as_dvec3() * d + across.as_dvec3() * d * theta_r.tan();
        assert!(
            close(path[2].origin(), exit, 1e-5),
            "{degrees}: {}",
            path[2].origin()
        );
        // Out parallel to the incoming ray...
        assert!(
            close(path[2].dir(), dir.as_dvec3(), 1e-5),
            "{degrees}: {}",
            path[2].dir()
        );
        // ... and off its line by d sin(theta_i - theta_r) / cos(theta_r).
        let offset = (path[2].origin() - ray.origin()).cross(dir).length() as f64;
        let expected = d * (theta_i - theta_r).sin() / theta_r.cos();
        assert!(
            (offset - expected).abs() < 1e-5,
            "{degrees} deg: offset {offset}, textbook {expected}"
        );
    }
}

/// A glass of index `ior` with these energies and no colour of its own.
fn glass(ior: f32, reflectance: f32, transmittance: f32, fresnel: bool) -> Glass {
    Glass {
        surface: Phong {
            ambient: Vec3::ZERO,
            diffuse: Vec3::ZERO,
            specular: Vec3::ZERO,
            shininess: 0.0,
            reflectance,
            texture: None,
            color_texture: None,
            emission: Vec3::ZERO,
            emission_texture: None,
            alpha_mask: None,
        },
        transmittance,
        ior,
        fresnel,
        absorption: Vec3::ZERO,
    }
}

#[test]
fn inside_a_slab_past_the_critical_angle_nothing_leaves() {
    let normal = slab_normal();
    for n in [1.5f64, 2.4] {
        let scene = slab_scene(n as f32, 0.5);
        let critical = (1.0 / n).asin();
        for (angle, leaves) in [
            (critical - 0.5f64.to_radians(), true),
            (critical + 0.5f64.to_radians(), false),
        ] {
            // From the middle of the slab up to its upper face.
            let (dir, across) = at_angle(normal, angle);
            let ray = Ray::new(across * 0.2, dir);
            let path = refracted_path(&scene, &ray, 10);
            let hit: SurfaceHit = scene
                .closest_hit(&ray, EPSILON, f32::INFINITY)
                .expect("the face");
            assert!(!hit.front_face, "from inside the face is met from behind");
            let degrees = angle.to_degrees();
            if leaves {
                assert_eq!(path.len(), 2, "n {n}, {degrees} deg: out");
                // Snell the other way: sin(theta_t) = n sin(theta_i), close to grazing.
                let theta_t = (n * angle.sin()).asin();
                let out = normal.as_dvec3() * theta_t.cos() + across.as_dvec3() * theta_t.sin();
                assert!(
                    close(path[1].dir(), out, 1e-4),
                    "n {n}, {degrees}: {}",
                    path[1].dir()
                );
            } else {
                assert_eq!(
                    path.len(),
                    1,
                    "n {n}, {degrees} deg: total internal reflection"
                );
            }
            // The split, without Fresnel: reflectance 0.1 and transmittance
            // 0.7 as given, or 0.8 all reflected when nothing can leave.
            let split = glass(n as f32, 0.1, 0.7, false).split(ray.dir(), &hit);
            if leaves {
                assert_eq!(split.reflected, 0.1);
                assert_eq!(split.transmitted.map(|(_, w)| w), Some(0.7));
            } else {
                assert!((split.reflected - 0.8).abs() < 1e-6, "{}", split.reflected);
                assert_eq!(split.transmitted, None);
            }
            // With Fresnel: the textbook reflectance from n to 1 (near 1
            // just below the critical angle), the rest times 0.7 through;
            // past it, everything reflected.
            let split = glass(n as f32, 0.0, 0.7, true).split(ray.dir(), &hit);
            let r = fresnel(n, 1.0, angle);
            if leaves {
                assert!(
                    (split.reflected as f64 - r).abs() < 1e-4,
                    "n {n}: {} vs {r}",
                    split.reflected
                );
                let (_, w) = split.transmitted.expect("some passes");
                assert!((w as f64 - 0.7 * (1.0 - r)).abs() < 1e-4, "n {n}: {w}");
            } else {
                assert_eq!(split.reflected, 1.0);
                assert_eq!(split.transmitted, None);
            }
        }
    }
}

/// A right-angled prism of index `ior`: the triangle (0, 0), (1, 0),
/// (0, 1) in x, y, from z = -1 to 1; its long face has normal (1, 1) / sqrt 2.
fn prism_scene(ior: f32) -> Scene {
    let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
    let (lo, hi) = (Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0));
    let mut triangles = vec![[a + lo, b + lo, c + lo], [a + hi, b + hi, c + hi]];
    for (p, q) in [(a, b), (b, c), (c, a)] {
        triangles.push([p + lo, q + lo, q + hi]);
        triangles.push([p + lo, q + hi, p + hi]);
    }
    let inside = (a + b + c) / 3.0;
    let materials = format!("[materials.glass]\ntransmittance = 1\nior = {ior:?}\n");
    scene_from(
        &Setup::one_ray(
            Vec3::new(0.3, 0.3, 20.0),
            Vec3::new(0.3, 0.3, 0.0),
            &materials,
        )
        .toml(&solid(&triangles, inside, "glass")),
    )
}

#[test]
fn a_prism_reflects_totally_above_index_sqrt_2_and_lets_light_out_below() {
    // Into the short face y = 0 square on (no bending), up to the long
    // face at 45 deg to its normal: past the critical angle asin(1 / n)
    // exactly when n > sqrt 2 = 1.41421.
    let ray = Ray::new(Vec3::new(0.3, -1.0, 0.2), Vec3::Y);
    let path = refracted_path(&prism_scene(1.43), &ray, 10);
    assert_eq!(path.len(), 2, "n 1.43: in, then reflected totally");
    assert!(close(path[1].dir(), DVec3::Y, 1e-6), "{}", path[1].dir());
    let path = refracted_path(&prism_scene(1.40), &ray, 10);
    assert_eq!(path.len(), 3, "n 1.40: in and out");
    // Out at theta_t from the long face's normal, sin(theta_t) = 1.4 sin 45
    // deg = 0.98995, on the side of the normal the ray went in along the
    // face: (0, 1) less its part along the normal is along (-1, 1).
    let theta_t = (1.4f64 * (PI / 4.0).sin()).asin();
    let normal = DVec3::new(1.0, 1.0, 0.0).normalize();
    let along = DVec3::new(-1.0, 1.0, 0.0).normalize();
    let out = normal * theta_t.cos() + along * theta_t.sin();
    assert!(
        close(path[2].dir(), out, 1e-4),
        "{} vs {out}",
        path[2].dir()
    );
    assert!(
        close(path[2].origin(), DVec3::new(0.3, 0.7, 0.2), 1e-6),
        "{}",
        path[2].origin()
    );
}

// 3. A ball lens.

/// Where the ray through a ball of radius `radius` and index `ior` at the
/// origin, coming in parallel to +z at height `h` in y, crosses the axis
/// after leaving it: its z, measured from the centre.
fn ball_lens_focus(ior: f32, radius: f32, h: f32) -> f32 {
    let materials = format!("[materials.glass]\ntransmittance = 1\nior = {ior:?}\n");
    let scene = scene_from(
        &Setup::one_ray(Vec3::new(0.0, 0.0, -20.0), Vec3::ZERO, &materials)
        .toml(&format!(
            "[[objects]]\nsphere = {{ center = [0, 0, 0], radius = {radius:?} }}\nmaterial = \"glass\"\n"
        )),
    );
    let ray = Ray::new(Vec3::new(0.0, h, -2.0 * radius), Vec3::Z);
    let path = refracted_path(&scene, &ray, 10);
    assert_eq!(path.len(), 3, "h {h}: in, through, out");
    let out = path[2];
    assert!(
        out.origin().x == 0.0 && out.dir().x == 0.0,
        "stays in the plane x = 0"
    );
    assert!(out.dir().y < 0.0, "h {h}: bent toward the axis");
    out.at(-out.origin().y / out.dir().y).z
}

#[test]
fn a_ball_lens_focuses_paraxial_rays_at_n_r_over_2_n_minus_1_from_its_centre() {
    let radius = 2.0f64;
    for n in [1.5f64, 1.8] {
        // The effective focal length, from the centre (paraxial optics).
        let paraxial = n * radius / (2.0 * (n - 1.0));
        for k in [0.01f64, 0.02, 0.03, 0.05] {
            let h = k * radius;
            let f = ball_lens_focus(n as f32, radius as f32, h as f32) as f64;
            // Exactly, by symmetry: the ray leaves at the angle to the normal
            // it came in at, so its line passes h from the centre, turned by
            // 2 (i - r), sin i = h / R, sin r = h / (n R); it crosses the
            // axis at h / sin(2 (i - r)) from the centre.
            let (i, r) = ((h / radius).asin(), (h / (n * radius)).asin());
            let exact = h / (2.0 * (i - r)).sin();
            // In f32: 3e-7 of f is the largest error seen.
            assert!(
                (f - exact).abs() < 2e-6 * paraxial,
                "n {n}, h {k} R: {f} vs exact {exact}"
            );
            // Spherical aberration: expanding the exact form in k = h / R,
            // f = paraxial (1 - c k^2 + O(k^4)) with c = b / a - 2 a^2 / 3,
            // a = 1 - 1 / n, b = (1 - 1 / n^3) / 6: 0.278 for n = 1.5,
            // 0.179 for 1.8 (7e-4 of f short at k = 0.05). So rays at small
            // heights focus short of the paraxial focus by c k^2, to 2% of
            // it (the k^4 term is 0.04% at k = 0.05) and the rounding.
            let a = 1.0 - 1.0 / n;
            let c = (1.0 - 1.0 / n.powi(3)) / 6.0 / a - 2.0 * a * a / 3.0;
            let short = (paraxial - f) / paraxial;
            assert!(
                (short - c * k * k).abs() < 0.02 * c * k * k + 5e-7,
                "n {n}, h {k} R: {f} is {short} short of {paraxial}, not {}",
                c * k * k
            );
        }
    }
}

// 5. and 6. Looking square on at a slab, with a one-pixel camera: the
// ray through the centre of a 1 x 1 image is the view direction.

/// The one pixel of a camera at `eye` looking at the origin, over a slab
/// from z = 0 down to z = -`thickness` of material `glass` (in
/// `materials`); with `behind`, a wall at z = 8 behind the camera showing
/// ambient `behind` under a white light (no diffuse, so exactly that).
fn one_pixel(
    eye: Vec3,
    materials: &str,
    thickness: f32,
    behind: Option<Vec3>,
    max_depth: u32,
    background: Vec3,
) -> Vec3 {
    let mut objects = slab(
        Vec3::new(0.0, 0.0, -thickness / 2.0),
        Vec3::Z,
        thickness,
        "glass",
    );
    let mut materials = materials.to_string();
    if let Some(ambient) = behind {
        materials += &format!("[materials.wall]\nambient = {}\n", arr(ambient));
        // A box whose face at z = 8 faces the slab (normals out).
        objects += &cuboid(
            Vec3::new(0.0, 0.0, 9.0),
            [Vec3::X, Vec3::Y, Vec3::Z],
            [10.0, 10.0, 1.0],
            "wall",
        );
    }
    let scene = scene_from(
        &Setup {
            eye,
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            size: (1, 1),
            max_depth,
            // Only the depth ends the ray tree, so it can be counted.
            min_energy: 0.0,
            background,
            light: (Vec3::new(0.0, 3.0, 4.0), Vec3::ONE),
            materials: &materials,
        }
        .toml(&objects),
    );
    render_image(&scene).get(0, 0)
}

/// `one_pixel` from z = 5 straight down the slab's normal.
fn square_on(
    materials: &str,
    thickness: f32,
    behind: Option<Vec3>,
    max_depth: u32,
    background: Vec3,
) -> Vec3 {
    let eye = Vec3::new(0.0, 0.0, 5.0);
    one_pixel(eye, materials, thickness, behind, max_depth, background)
}

/// Square on, a non-absorbing slab with Fresnel: every surface reflects
/// R = ((n - 1) / (n + 1))^2 and passes T = 1 - R. The ray tree: the front
/// face at depth 0 reflects R toward the camera side; what goes in meets
/// the faces again and again, the m-th meeting (m >= 2) sending out
/// T^2 R^(m - 2), through the back face when m is even, back through the
/// front when m is odd. A ray of depth k spawns only if k < max_depth, so
/// meetings up to m = max_depth send light out. Returns (what leaves
/// toward the camera side, what leaves behind), per unit of light.
fn slab_tree(n: f64, max_depth: u32) -> (f64, f64) {
    let r = ((n - 1.0) / (n + 1.0)).powi(2);
    let t = 1.0 - r;
    let (mut front, mut back) = (0.0, 0.0);
    if max_depth >= 1 {
        front += r;
    }
    for m in 2..=max_depth {
        let out = t * t * r.powi(m as i32 - 2);
        if m % 2 == 0 {
            back += out;
        } else {
            front += out;
        }
    }
    (front, back)
}

fn fresnel_glass(ior: f64) -> String {
    format!("[materials.glass]\ntransmittance = 1\nfresnel = true\nior = {ior:?}\n")
}

#[test]
fn fresnel_glass_square_on_reflects_the_textbook_fraction_of_what_is_behind_the_camera() {
    // Red-orange behind the camera, blue beyond the slab, so the
    // reflected and the transmitted light are told apart by channel.
    let (wall, sky) = (DVec3::new(0.8, 0.2, 0.0), DVec3::new(0.0, 0.3, 0.9));
    for n in [1.5f64, 2.4] {
        let r = ((n - 1.0) / (n + 1.0)).powi(2);
        // Depth 1: only the front face's mirror ray, R = 0.04 (n 1.5) or
        // 0.16955 (n 2.4) of the wall.
        let c = square_on(
            &fresnel_glass(n),
            0.5,
            Some(wall.as_vec3()),
            1,
            sky.as_vec3(),
        );
        assert!(close(c, wall * r, 1e-6), "n {n}: {c} vs {}", wall * r);
        // Deeper, the inside bounces add up as the tree says.
        for d in [2, 3, 4, 6] {
            let (front, back) = slab_tree(n, d);
            let expected = wall * front + sky * back;
            let c = square_on(
                &fresnel_glass(n),
                0.5,
                Some(wall.as_vec3()),
                d,
                sky.as_vec3(),
            );
            assert!(
                close(c, expected, 1e-6),
                "n {n}, depth {d}: {c} vs {expected}"
            );
        }
    }
}

#[test]
fn fresnel_glass_square_on_with_the_same_light_all_round_conserves_energy() {
    // All light that goes in comes out somewhere: R + T^2 sum R^2k (back)
    // + T^2 R sum R^2k (front) = R + T^2 / (1 - R) = R + T = 1. With the
    // same background all round the pixel tends to it; at depth d what is
    // missing is the light still inside, T R^(d - 1).
    let background = DVec3::new(0.9, 0.6, 0.3);
    for n in [1.5f64, 2.4] {
        let r = ((n - 1.0) / (n + 1.0)).powi(2);
        for d in [1u32, 2, 3, 5, 12] {
            let c = square_on(&fresnel_glass(n), 0.5, None, d, background.as_vec3());
            let (front, back) = slab_tree(n, d);
            let inside = (1.0 - r) * r.powi(d as i32 - 1);
            assert!((front + back + inside - 1.0).abs() < 1e-12);
            let expected = background * (1.0 - inside);
            assert!(
                close(c, expected, 1e-6),
                "n {n}, depth {d}: {c} vs {expected}"
            );
        }
        let c = square_on(&fresnel_glass(n), 0.5, None, 12, background.as_vec3());
        assert!(close(c, background, 1e-6), "n {n}: {c}");
    }
}

#[test]
fn absorbing_glass_passes_exp_minus_a_l_of_the_background() {
    // Beer-Lambert: after L inside, exp(-a L) per channel. ior 1 goes
    // straight, without Fresnel nothing is reflected, so the background
    // comes back through the slab dimmed by exactly that.
    let a = DVec3::new(0.1, 0.5, 2.0);
    let background = DVec3::new(0.9, 0.8, 0.7);
    for ior in [1.0f64, 1.5] {
        let materials = format!(
            "[materials.glass]\ntransmittance = 1\nior = {ior:?}\nabsorption = {}\n",
            arr(a.as_vec3())
        );
        for l in [0.25f64, 0.5, 2.0] {
            let c = square_on(&materials, l as f32, None, 4, background.as_vec3());
            let expected = background * (-a * l).exp();
            assert!(
                close(c, expected, 1e-6),
                "ior {ior}, L {l}: {c} vs {expected}"
            );
        }
    }
}

// 7. Shadows through glass.

/// The floor point at the origin seen from straight above, lit by one
/// light at (4, 6, 0) whose way to it passes `h` from the centre of a
/// glass ball of radius 0.5 (material `glass` in `materials`), or no ball
/// for `None`; the ball is 2 away from the camera's ray, out of its sight.
fn floor_behind_a_ball(materials: &str, h: Option<f32>) -> Vec3 {
    // Halfway to the light, and h across it along z (square to the
    // segment, which lies in z = 0).
    let centre = Vec3::new(2.0, 3.0, h.unwrap_or(0.0));
    let floor = floor_square(10.0);
    let mut objects = String::new();
    for [a, b, c] in floor {
        // Normals up, toward the light and the camera.
        assert!((b - a).cross(c - a).y > 0.0);
        objects += &format!(
            "[[objects]]\ntriangle = [{}, {}, {}]\nmaterial = \"floor\"\n",
            arr(a),
            arr(b),
            arr(c)
        );
    }
    if h.is_some() {
        objects += &format!(
            "[[objects]]\nsphere = {{ center = {}, radius = 0.5 }}\nmaterial = \"glass\"\n",
            arr(centre)
        );
    }
    let materials = format!(
        "{materials}[materials.floor]\nambient = [0.1, 0.1, 0.1]\ndiffuse = [0.6, 0.5, 0.4]\n\
         specular = [0.4, 0.4, 0.4]\nshininess = 10\n"
    );
    let scene = scene_from(
        &Setup {
            eye: Vec3::new(0.0, 5.0, 0.0),
            look_at: Vec3::ZERO,
            up: Vec3::new(0.0, 0.0, -1.0),
            size: (1, 1),
            max_depth: 8,
            min_energy: 0.01,
            background: Vec3::ZERO,
            light: (Vec3::new(4.0, 6.0, 0.0), Vec3::new(0.9, 0.8, 0.7)),
            materials: &materials,
        }
        .toml(&objects),
    );
    render_image(&scene).get(0, 0)
}

/// The lab's Blinn-Phong at the origin of the floor above, by hand, with
/// the light dimmed by `through`: ambient + through * light (kd cos a +
/// ks cos b ^ shininess), cos a = n . l, cos b = n . normalize(l + v).
fn floor_colour(through: f64) -> DVec3 {
    let light = DVec3::new(0.9, 0.8, 0.7);
    let (ka, kd, ks) = (
        DVec3::splat(0.1),
        DVec3::new(0.6, 0.5, 0.4),
        DVec3::splat(0.4),
    );
    let n = DVec3::Y;
    let l = DVec3::new(4.0, 6.0, 0.0).normalize();
    let v = DVec3::Y;
    // cos a = 6 / sqrt 52 = 0.83205, cos b = 0.95709.
    let (cos_a, cos_b) = (n.dot(l), n.dot((l + v).normalize()));
    light * ka + through * light * (kd * cos_a + ks * cos_b.powf(10.0))
}

#[test]
fn a_glass_ball_lets_transmittance_squared_of_the_light_through_its_shadow() {
    // Without the ball, the full light: the scene's arithmetic is right.
    let lit = floor_colour(1.0);
    let c = floor_behind_a_ball("", None);
    assert!(close(c, lit, 1e-5), "{c} vs {lit}");
    // Shadow rays go straight (no caustics): through two surfaces of
    // transmittance t the light is t^2 of itself, whatever the index, and
    // whether the straight line passes the ball's centre or near its rim
    // (h = 0.8 R: past the critical angle of n = 1.5 if the line were a
    // ray inside, but the light that really gets through was bent on the
    // way in and meets the far side at the angle it was bent to).
    let t = 0.6f64;
    let dark = floor_colour(0.0);
    let expected = floor_colour(t * t);
    for ior in [1.0f64, 1.5, 2.4] {
        let materials = format!("[materials.glass]\ntransmittance = {t:?}\nior = {ior:?}\n");
        for h in [0.0f32, 0.25, 0.4] {
            let c = floor_behind_a_ball(&materials, Some(h));
            assert!(
                close(c, expected, 1e-5),
                "ior {ior}, {h} from the centre: {c}, expected {expected} \
                 (lit {lit}, ambient only {dark})"
            );
        }
    }
    // With Fresnel, each surface passes t (1 - F): in at i from the
    // normal, sin i = h / R, F(i) from 1 to n; out at the bent angle r,
    // where F from n to 1 is F(i) again (reciprocity, Stokes).
    for ior in [1.5f64, 2.4] {
        let materials =
            format!("[materials.glass]\ntransmittance = {t:?}\nior = {ior:?}\nfresnel = true\n");
        for h in [0.0f32, 0.25, 0.4] {
            let i = (h as f64 / 0.5).asin();
            let r = (i.sin() / ior).asin();
            assert!((fresnel(ior, 1.0, r) - fresnel(1.0, ior, i)).abs() < 1e-12);
            let pass = t * (1.0 - fresnel(1.0, ior, i));
            let expected = floor_colour(pass * pass);
            let c = floor_behind_a_ball(&materials, Some(h));
            assert!(
                close(c, expected, 1e-5),
                "fresnel, ior {ior}, {h} from the centre: {c}, expected {expected}"
            );
        }
    }
}

/// The square floor y = 0 from -half to half on x and z, as two triangles.
fn floor_square(half: f32) -> [[Vec3; 3]; 2] {
    let corner = |x: f32, z: f32| Vec3::new(x * half, 0.0, z * half);
    [
        [corner(-1.0, -1.0), corner(-1.0, 1.0), corner(1.0, 1.0)],
        [corner(-1.0, -1.0), corner(1.0, 1.0), corner(1.0, -1.0)],
    ]
}

/// Glass in a mirror ball, `max_depth = 64`, `min_energy = 0`: every glass
/// hit splits the ray in two, so a tree could reach 2^64 rays. Each sample
/// traces at most MAX_TREE_RAYS of them (the render took hours, `explain`
/// ran out of memory).
#[test]
fn a_ray_tree_that_doubles_at_every_level_is_cut_at_its_budget() {
    use tracer_core::integrate::whitted::MAX_TREE_RAYS;
    let text = "[camera]\neye = [0.3, 0.2, 3]\nlook_at = [0, 0, 0]\nwidth = 4\nheight = 4\n\
                [render]\nmax_depth = 64\nmin_energy = 0\n\
                [[lights]]\nposition = [0, 2, 2]\n\
                [materials.glass]\nreflectance = 0.5\ntransmittance = 0.5\nior = 1.5\n\
                [materials.mirror]\nreflectance = 1\n\
                [[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\nmaterial = \"glass\"\n\
                [[objects]]\nsphere = { center = [0, 0, 0], radius = 10 }\nmaterial = \"mirror\"\n";
    let scene = scene_from(text);
    let rendered = render(&scene, &RenderJob::full(&scene), &|_| {});
    let rays = rendered.rays;
    // The pixels that see the glass ball grow past the budget (the mirror
    // alone makes one ray a level); no sample traces more than the budget
    // and its primary ray.
    assert!((1..=16).contains(&rays.cut_trees), "{rays:?}");
    assert!(
        rays.nearest <= 16 * (u64::from(MAX_TREE_RAYS) + 1),
        "{rays:?}"
    );
    assert!(rendered.image.pixels.iter().all(|p| p.is_finite()));
}
