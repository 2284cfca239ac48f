//! `tracer explain`'s text: an explained pixel's tree in the lab's words and
//! order. One formatter for `tracer explain`, the live page of `tracer
//! watch --serve` and the browser playground (crates/web), so that all
//! three say the same.

use crate::explain::{
    ExplainedPixel, Lit, Outcome, PathEvent, PathEventKind, RayKind, RayNode, Saturation, Stop,
    Trace,
};
use crate::load::Loaded;
use crate::options::Options;
use crate::Error;
use glam::{Vec2, Vec3};
use std::fmt::Write;
use tracer_core::names::Names;

/// Pixel (x, y)'s tree as text, its sample `sample`'s (0 the first):
/// what a click on the image shows in `tracer watch --serve`'s page and in
/// the playground.
pub fn tree_text(
    loaded: &Loaded,
    options: &Options,
    (x, y): (u32, u32),
    sample: u32,
) -> Result<String, Error> {
    let pixel = crate::explain::explain(loaded, options, (x, y), sample)?;
    Ok(text(&pixel, (x, y), &loaded.name.display().to_string()))
}

fn v3(v: Vec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", v.x, v.y, v.z)
}

fn v2(v: Vec2) -> String {
    format!("({:.4}, {:.4})", v.x, v.y)
}

/// The explanation of pixel (x, y) of the scene `name` as text.
pub fn text(pixel: &ExplainedPixel, (x, y): (u32, u32), name: &str) -> String {
    let e = &pixel.explanation;
    let (width, height) = pixel.size;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "pixel ({x}, {y}) of {name} ({width}x{height}; X from the left, Y from the top), {}",
        if e.samples == 1 {
            "its one sample, through the pixel's centre".to_string()
        } else {
            format!("sample {} of {}", e.sample, e.samples)
        }
    );
    let [u, v, o] = e.projection;
    let _ = writeln!(
        out,
        "primary ray (lab 1.2.3): direction = normalize(P (x, y, 1)) with P = [u v o],\n  u = {}, v = {}, o = {},\n  image point (x, y) = {}{}",
        v3(u),
        v3(v),
        v3(o),
        v2(e.image_point),
        if e.lens_point == Vec2::ZERO {
            String::new()
        } else {
            format!(", lens point {}", v2(e.lens_point))
        }
    );
    match &e.trace {
        Trace::Whitted { ray } => ray_text(&mut out, ray, 0, &pixel.names),
        Trace::Path { ray, events } => {
            ray_text(&mut out, ray, 0, &pixel.names);
            path_text(&mut out, events, &pixel.names);
        }
    }
    encoding_text(&mut out, pixel);
    out
}

/// A ray of the tree, its children indented below it.
fn ray_text(out: &mut String, ray: &RayNode, indent: usize, names: &Names) {
    let pad = "  ".repeat(indent);
    let kind = match ray.kind {
        RayKind::Primary => "primary ray",
        RayKind::Reflected => "mirror ray",
        RayKind::Refracted => "refracted ray",
    };
    let _ = writeln!(
        out,
        "{pad}{kind} from {} along {}, energy {}, depth {}",
        v3(ray.origin),
        v3(ray.direction),
        ray.energy,
        ray.depth
    );
    if let Some(tested) = &ray.tested {
        let mut missed = Vec::new();
        for t in tested {
            let what = match t.outcome {
                Outcome::Nearest { t } => format!("hit at t = {t:.4}, the nearest"),
                Outcome::Farther { t } => format!("hit at t = {t:.4}, farther than the nearest"),
                // A hit a hair behind the origin is the surface the ray
                // left (acne's cause): its t in full, not -0.0000.
                Outcome::Behind { t } if t.abs() <= tracer_core::EPSILON => {
                    format!("met within the lab's 1e-4 of the ray's origin (t = {t:e}): the surface it leaves, not a hit")
                }
                Outcome::Behind { t } => format!("met behind the ray's origin (t = {t:.4})"),
                Outcome::Missed => {
                    missed.push(t.object);
                    continue;
                }
            };
            let _ = writeln!(out, "{pad}  {}: {what}", names.object(t.object));
        }
        if !missed.is_empty() {
            let _ = writeln!(out, "{pad}  missed: {}", names.objects(&missed));
        }
    }
    let Some(hit) = &ray.hit else {
        let _ = writeln!(
            out,
            "{pad}  nothing hit: the background, times the energy = {}",
            v3(ray.colour)
        );
        return;
    };
    let _ = writeln!(
        out,
        "{pad}  nearest hit: {} at t = {:.4}, point {}, normal {}, {} side, material {}, uv {}",
        names.object(hit.object),
        hit.t,
        v3(hit.point),
        v3(hit.normal),
        if hit.front_face { "front" } else { "back" },
        names.material(hit.material),
        v2(hit.uv)
    );
    if !hit.front_face && ray.ambient.is_empty() && ray.local.is_none() {
        let _ = writeln!(
            out,
            "{pad}  seen from inside the glass: no light terms (the lab adds them where a surface is seen from outside)"
        );
    }
    for (light, ambient) in &ray.ambient {
        let _ = writeln!(
            out,
            "{pad}  lights[{light}]: ambient = color * ambient = {}",
            v3(*ambient)
        );
        for lit in ray.lights.iter().filter(|l| l.term.light == *light) {
            light_text(out, lit, &pad, names);
        }
    }
    if let Some(local) = ray.local {
        let _ = writeln!(
            out,
            "{pad}  local colour (the sum of the terms) = {}",
            v3(local)
        );
    }
    if let Some(texture) = ray.texture {
        let _ = writeln!(out, "{pad}  times the lab texture {}", v3(texture));
    }
    if let Some(emitted) = ray.emitted {
        let _ = writeln!(
            out,
            "{pad}  plus its emission {} (seen; in Whitted mode it lights nothing else)",
            v3(emitted)
        );
    }
    match ray.stopped {
        Some(Stop::MaxDepth { max_depth }) => {
            let _ = writeln!(
                out,
                "{pad}  no mirror or refracted ray: depth {} is max_depth = {max_depth}",
                ray.depth
            );
        }
        Some(Stop::RayBudget { rays }) => {
            let _ = writeln!(
                out,
                "{pad}  no more rays: the sample has traced its {rays} (a budget that keeps a tree of glass and mirrors finite)"
            );
        }
        Some(Stop::MinEnergy { min_energy }) => {
            let _ = writeln!(
                out,
                "{pad}  no mirror or refracted ray: energy {} is at or below min_energy = {min_energy}",
                ray.energy
            );
        }
        None => {}
    }
    for child in &ray.children {
        ray_text(out, child, indent + 1, names);
    }
    if let Some(absorbed) = ray.absorbed {
        let _ = writeln!(
            out,
            "{pad}  times what absorption leaves of it through the glass, exp(-absorption * t) = {}",
            v3(absorbed)
        );
    }
    let _ = writeln!(
        out,
        "{pad}  colour of this ray (times its energy, with its mirror and refracted rays) = {}",
        v3(ray.colour)
    );
}

/// One light's terms at a hit.
fn light_text(out: &mut String, lit: &Lit, pad: &str, names: &Names) {
    let t = &lit.term;
    let _ = writeln!(
        out,
        "{pad}    from {}: L = {}, N.L = {:.4}",
        v3(t.from),
        v3(t.l),
        t.n_dot_l
    );
    let Some(shadow) = &t.shadow else {
        let _ = writeln!(
            out,
            "{pad}      N.L at or below 0.001: no diffuse, no specular, no shadow ray"
        );
        return;
    };
    let blocked = match (shadow.passes, lit.blocked_by) {
        (Some(p), _) if p == Vec3::ONE => "clear".to_string(),
        (Some(p), _) => format!("through glass, passing {}", v3(p)),
        (None, Some(b)) => format!("blocked by {} at t = {:.4}", names.object(b.object), b.t),
        (None, None) => "blocked".to_string(),
    };
    let _ = writeln!(
        out,
        "{pad}      shadow ray from {} of length {:.4}: {blocked}",
        v3(shadow.origin),
        shadow.length
    );
    if shadow.passes.is_none() {
        return;
    }
    let _ = writeln!(
        out,
        "{pad}      diffuse = color * diffuse * N.L = {}",
        v3(t.diffuse)
    );
    if let (Some(h), Some(n_dot_h)) = (t.h, t.n_dot_h) {
        let specular = match t.n_dot_h_pow {
            Some(power) => format!(
                "(N.H)^n = {power:.6}, specular = color * specular * (N.H)^n = {}",
                v3(t.specular)
            ),
            None if n_dot_h <= 0.001 => "no specular: N.H at or below 0.001".to_string(),
            None => "no specular: the material has no specular colour".to_string(),
        };
        let _ = writeln!(
            out,
            "{pad}      H = normalize(L + V) = {}, N.H = {n_dot_h:.4}, {specular}",
            v3(h)
        );
    }
}

/// A path's events, for one sample.
fn path_text(out: &mut String, events: &[PathEvent], names: &Names) {
    let _ = writeln!(
        out,
        "the path (one sample; MIS weights by the power heuristic):"
    );
    for event in events {
        let added = if event.added == Vec3::ZERO {
            String::new()
        } else {
            format!(" -> adds {}", v3(event.added))
        };
        let line = match event.kind {
            PathEventKind::Vertex {
                depth,
                point,
                normal,
                material,
                front_face,
            } => format!(
                "vertex {depth}: point {}, normal {}, {} side, material {}, throughput {}",
                v3(point),
                v3(normal),
                if front_face { "front" } else { "back" },
                names.material(material),
                v3(event.throughput)
            ),
            PathEventKind::Emitted { radiance, weight } => {
                format!("  emitted {} x MIS weight {weight:.4}{added}", v3(radiance))
            }
            PathEventKind::Escaped { radiance, weight } => format!(
                "left the scene: {} x MIS weight {weight:.4}{added}",
                v3(radiance)
            ),
            PathEventKind::LightSample {
                wi,
                distance,
                radiance,
                light_pdf,
                f_cos,
                bsdf_pdf,
                weight,
                blocked,
                absorbed,
            } => format!(
                "  light sample toward {} (distance {distance:.4}): radiance {}{}, light pdf {light_pdf:.4}, f cos {}, BSDF pdf {bsdf_pdf:.4}, MIS weight {weight:.4}, {}{added}",
                v3(wi),
                v3(radiance),
                if absorbed == Vec3::ONE {
                    String::new()
                } else {
                    format!(" times {} left by the glass around", v3(absorbed))
                },
                v3(f_cos),
                if f_cos == Vec3::ZERO {
                    "the surface sends nothing that way (no shadow ray)"
                } else if blocked {
                    "its shadow ray blocked"
                } else {
                    "its shadow ray clear"
                }
            ),
            PathEventKind::BsdfSample {
                wi,
                weight,
                pdf,
                specular,
            } => format!(
                "  BSDF sample toward {}: f cos / pdf = {}, pdf {pdf:.4}{}",
                v3(wi),
                v3(weight),
                if specular { " (a specular lobe)" } else { "" }
            ),
            PathEventKind::NoLightPoint => {
                "  light sample: the light picked has no point that can light this one (it faces away, or its sample came to nothing)".to_string()
            }
            PathEventKind::Roulette { survive, survived } => format!(
                "  Russian roulette: goes on with probability {survive:.4}: {}",
                if survived { "it does (throughput / that)" } else { "it stops" }
            ),
        };
        let _ = writeln!(out, "{line}");
    }
}

/// The pixel's sum, saturation rule, gamma and 8-bit value.
fn encoding_text(out: &mut String, pixel: &ExplainedPixel) {
    let e = &pixel.explanation;
    let c = pixel.linear;
    let _ = writeln!(out, "this sample's colour = {}", v3(e.colour));
    if !e.colour.is_finite() {
        let _ = writeln!(
            out,
            "  not a finite number: the render leaves this sample out of the pixel (and counts it)"
        );
    }
    let _ = writeln!(
        out,
        "pixel colour (linear) = {} {}",
        v3(c),
        if e.samples == 1 {
            "(the one sample's)".to_string()
        } else {
            format!("(the mean of its {} samples)", e.samples)
        }
    );
    let encoding = &pixel.encoding;
    let saturated = match encoding.saturation {
        Saturation::White if c.max_element() > 1.0 => {
            "saturation rule \"white\" (the lab's): a channel above 1, so the pixel is white"
                .to_string()
        }
        Saturation::White => {
            "saturation rule \"white\" (the lab's): no channel above 1".to_string()
        }
        Saturation::Clamp => {
            "saturation rule \"clamp\": each channel clamped to 0..1 on its own".to_string()
        }
    };
    let _ = writeln!(out, "{saturated}");
    let _ = writeln!(
        out,
        "gamma {}: c^(1/{}) on each channel; 8-bit: (int)(c * 255) = ({}, {}, {}), the rendered pixel",
        encoding.gamma, encoding.gamma, pixel.rgb8[0], pixel.rgb8[1], pixel.rgb8[2]
    );
}
