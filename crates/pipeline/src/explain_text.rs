//! `tracer explain`'s text: an explained pixel's tree in the lab's words and
//! order. One formatter for `tracer explain`, the live page of `tracer
//! watch --serve` and the browser playground (crates/web), so that all
//! three say the same. Written as it is made (`write_text`), never held
//! whole, with the control characters of names escaped
//! (`scene_format::visible`).

use crate::explain::{
    Cut, ExplainedPixel, Lit, Outcome, PathEvent, PathEventKind, RayKind, RayNode, Saturation,
    Stop, Trace,
};
use crate::load::Loaded;
use crate::options::Options;
use crate::Error;
use glam::{Vec2, Vec3};
use scene_format::visible::VisibleWriter;
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
pub fn text(pixel: &ExplainedPixel, at: (u32, u32), name: &str) -> String {
    let mut out = String::new();
    // Writing to a String cannot fail.
    let _ = write_text(&mut out, pixel, at, name);
    out
}

/// [`text`], written to `out` as it is made: a tree raised to millions of
/// events (`--max-events`) is never held whole as text. Control
/// characters (in a material's or the scene's name) are escaped.
pub fn write_text(
    out: &mut dyn Write,
    pixel: &ExplainedPixel,
    at: (u32, u32),
    name: &str,
) -> std::fmt::Result {
    let mut visible = VisibleWriter { inner: out };
    write_all(&mut visible, pixel, at, name)
}

fn write_all(
    out: &mut dyn Write,
    pixel: &ExplainedPixel,
    (x, y): (u32, u32),
    name: &str,
) -> std::fmt::Result {
    let e = &pixel.explanation;
    let (width, height) = pixel.size;
    writeln!(
        out,
        "pixel ({x}, {y}) of {name} ({width}x{height}; X from the left, Y from the top), {}",
        if e.samples == 1 {
            "its one sample, through the pixel's centre".to_string()
        } else {
            format!("sample {} of {}", e.sample, e.samples)
        }
    )?;
    if let Some(cut) = &e.cut {
        cut_text(out, cut)?;
    }
    if let Some(light) = e.only_light {
        writeln!(
            out,
            "only the terms of lights[{light}] are shown (--light {light}); each local colour is still the sum of every light's"
        )?;
    }
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
        Trace::Whitted { ray } => ray_text(out, ray, 0, &pixel.names)?,
        Trace::Path { ray, events } => {
            ray_text(out, ray, 0, &pixel.names)?;
            path_text(out, events, &pixel.names)?;
            if let Some(cut) = e.cut.filter(|c| c.left_out > 0) {
                writeln!(
                    out,
                    "  ... and {} more events, not kept (the tree's limit)",
                    cut.left_out
                )?;
            }
        }
    }
    encoding_text(out, pixel)
}

/// What the tree's limits left out, and how to see it.
fn cut_text(out: &mut dyn Write, cut: &Cut) -> std::fmt::Result {
    let limit = if cut.bytes {
        format!("its limit of {} MiB", tracer_core::explain::MAX_BYTES >> 20)
    } else {
        format!("its limit of {} events", cut.max_events)
    };
    let mut parts = Vec::new();
    if cut.rays > 0 {
        parts.push(format!("{} rays", cut.rays));
    }
    if cut.light_terms > 0 {
        parts.push(format!("{} light terms", cut.light_terms));
    }
    let what = if parts.is_empty() {
        String::new()
    } else {
        format!(", among them {}", parts.join(" and "))
    };
    writeln!(
        out,
        "note: the tree is cut at {limit}: {} events are shown and {} more are not{what} (marked \"not kept\" below). \
         The colours are the whole sample's. To see more: tracer explain SCENE X Y --max-events N, \
         or --light K for the terms of lights[K] alone",
        cut.kept, cut.left_out
    )
}

/// A ray of the tree, its children indented below it.
fn ray_text(out: &mut dyn Write, ray: &RayNode, indent: usize, names: &Names) -> std::fmt::Result {
    let pad = "  ".repeat(indent);
    let kind = match ray.kind {
        RayKind::Primary => "primary ray",
        RayKind::Reflected => "mirror ray",
        RayKind::Refracted => "refracted ray",
    };
    writeln!(
        out,
        "{pad}{kind} from {} along {}, energy {}, depth {}",
        v3(ray.origin),
        v3(ray.direction),
        ray.energy,
        ray.depth
    )?;
    if let Some(tested) = &ray.tested {
        let mut missed = Vec::new();
        for t in tested {
            let what = match t.outcome {
                Outcome::Nearest { t } => format!("hit at t = {t:.4}, the nearest"),
                Outcome::Farther { t } => format!("hit at t = {t:.4}, farther than the nearest"),
                Outcome::Cutout { t } => {
                    format!("met at t = {t:.4} in a hole: its material's alpha_cutoff cuts it out")
                }
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
            writeln!(out, "{pad}  {}: {what}", names.object(t.object))?;
        }
        if !missed.is_empty() {
            writeln!(out, "{pad}  missed: {}", names.objects(&missed))?;
        }
    }
    let Some(hit) = &ray.hit else {
        writeln!(
            out,
            "{pad}  nothing hit: the background, times the energy = {}",
            v3(ray.colour)
        )?;
        return Ok(());
    };
    writeln!(
        out,
        "{pad}  nearest hit: {} at t = {:.4}, point {}, normal {}, {} side, material {}, uv {}",
        names.object(hit.object),
        hit.t,
        v3(hit.point),
        v3(hit.normal),
        if hit.front_face { "front" } else { "back" },
        names.material(hit.material),
        v2(hit.uv)
    )?;
    if !hit.front_face && ray.ambient.is_empty() && ray.local.is_none() {
        writeln!(
            out,
            "{pad}  seen from inside the glass: no light terms (the lab adds them where a surface is seen from outside)"
        )?;
    }
    for (light, ambient) in &ray.ambient {
        writeln!(
            out,
            "{pad}  lights[{light}]: ambient = color * ambient = {}",
            v3(*ambient)
        )?;
        for lit in ray.lights.iter().filter(|l| l.term.light == *light) {
            light_text(out, lit, &pad, names)?;
        }
    }
    if ray.left_out.light_terms > 0 {
        writeln!(
            out,
            "{pad}  ... and {} more light terms, not kept (the tree's limit; its local colour holds them)",
            ray.left_out.light_terms
        )?;
    }
    if let Some(local) = ray.local {
        writeln!(
            out,
            "{pad}  local colour (the sum of the terms) = {}",
            v3(local)
        )?;
    }
    if let Some(texture) = ray.texture {
        writeln!(out, "{pad}  times the lab texture {}", v3(texture))?;
    }
    if let Some(emitted) = ray.emitted {
        writeln!(
            out,
            "{pad}  plus its emission {} (seen; in Whitted mode it lights nothing else)",
            v3(emitted)
        )?;
    }
    match ray.stopped {
        Some(Stop::MaxDepth { max_depth }) => {
            writeln!(
                out,
                "{pad}  no mirror or refracted ray: depth {} is max_depth = {max_depth}",
                ray.depth
            )?;
        }
        Some(Stop::RayBudget { rays }) => {
            writeln!(
                out,
                "{pad}  no more rays: the sample has traced its {rays} (a budget that keeps a tree of glass and mirrors finite)"
            )?;
        }
        Some(Stop::MinEnergy { min_energy }) => {
            writeln!(
                out,
                "{pad}  no mirror or refracted ray: energy {} is at or below min_energy = {min_energy}",
                ray.energy
            )?;
        }
        None => {}
    }
    for child in &ray.children {
        ray_text(out, child, indent + 1, names)?;
    }
    if ray.left_out.rays > 0 {
        writeln!(
            out,
            "{pad}  ... and {} more mirror or refracted rays, with their own, not kept (the tree's limit; its colour holds them)",
            ray.left_out.rays
        )?;
    }
    if let Some(absorbed) = ray.absorbed {
        writeln!(
            out,
            "{pad}  times what absorption leaves of it through the glass, exp(-absorption * t) = {}",
            v3(absorbed)
        )?;
    }
    writeln!(
        out,
        "{pad}  colour of this ray (times its energy, with its mirror and refracted rays) = {}",
        v3(ray.colour)
    )
}

/// One light's terms at a hit.
fn light_text(out: &mut dyn Write, lit: &Lit, pad: &str, names: &Names) -> std::fmt::Result {
    let t = &lit.term;
    writeln!(
        out,
        "{pad}    from {}: L = {}, N.L = {:.4}",
        v3(t.from),
        v3(t.l),
        t.n_dot_l
    )?;
    let Some(shadow) = &t.shadow else {
        writeln!(
            out,
            "{pad}      N.L at or below 0.001: no diffuse, no specular, no shadow ray"
        )?;
        return Ok(());
    };
    let blocked = match (shadow.passes, lit.blocked_by) {
        (Some(p), _) if p == Vec3::ONE => "clear".to_string(),
        (Some(p), _) => format!("through glass, passing {}", v3(p)),
        (None, Some(b)) => format!("blocked by {} at t = {:.4}", names.object(b.object), b.t),
        (None, None) => "blocked".to_string(),
    };
    writeln!(
        out,
        "{pad}      shadow ray from {} of length {:.4}: {blocked}",
        v3(shadow.origin),
        shadow.length
    )?;
    if shadow.passes.is_none() {
        return Ok(());
    }
    writeln!(
        out,
        "{pad}      diffuse = color * diffuse * N.L = {}",
        v3(t.diffuse)
    )?;
    if let (Some(h), Some(n_dot_h)) = (t.h, t.n_dot_h) {
        let specular = match t.n_dot_h_pow {
            Some(power) => format!(
                "(N.H)^n = {power:.6}, specular = color * specular * (N.H)^n = {}",
                v3(t.specular)
            ),
            None if n_dot_h <= 0.001 => "no specular: N.H at or below 0.001".to_string(),
            None => "no specular: the material has no specular colour".to_string(),
        };
        writeln!(
            out,
            "{pad}      H = normalize(L + V) = {}, N.H = {n_dot_h:.4}, {specular}",
            v3(h)
        )?;
    }
    Ok(())
}

/// A path's events, for one sample.
fn path_text(out: &mut dyn Write, events: &[PathEvent], names: &Names) -> std::fmt::Result {
    writeln!(
        out,
        "the path (one sample; MIS weights by the power heuristic):"
    )?;
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
        writeln!(out, "{line}")?;
    }
    Ok(())
}

/// The pixel's sum, saturation rule, gamma and 8-bit value.
fn encoding_text(out: &mut dyn Write, pixel: &ExplainedPixel) -> std::fmt::Result {
    let e = &pixel.explanation;
    let c = pixel.linear;
    writeln!(out, "this sample's colour = {}", v3(e.colour))?;
    if !e.colour.is_finite() {
        writeln!(
            out,
            "  not a finite number: the render leaves this sample out of the pixel (and counts it)"
        )?;
    }
    writeln!(
        out,
        "pixel colour (linear) = {} {}",
        v3(c),
        match pixel.paths {
            1 => "(the one sample's)".to_string(),
            n if n == e.samples => format!("(the mean of its {n} samples)"),
            n => format!(
                "(the mean of its {n} paths: adaptive sampling's share for it of the image's mean of {})",
                e.samples
            ),
        }
    )?;
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
    writeln!(out, "{saturated}")?;
    writeln!(
        out,
        "gamma {}: c^(1/{}) on each channel; 8-bit: (int)(c * 255) = ({}, {}, {}), the rendered pixel",
        encoding.gamma, encoding.gamma, pixel.rgb8[0], pixel.rgb8[1], pixel.rgb8[2]
    )
}
