//! `tracer explain SCENE X Y`: why a pixel has its colour, in the lab's
//! words and order (lab sections 1.2.3, 4 and 5): the primary ray, what it
//! met, each light's terms and shadow ray, the mirror and refracted rays,
//! then the sum, the saturation rule, gamma and the 8-bit value, which is
//! the rendered pixel's. In path mode, one sample's path: its vertices,
//! light and BSDF samples and their MIS weights. `--json` gives the same
//! as JSON (its structure documented in the book, docs/src/reference/explain-json.md, versioned).

use crate::args::Explain;
use crate::console;
use anyhow::Result;
use tracer_pipeline::explain::{ExplainedPixel, Saturation, Trace};
use tracer_pipeline::explain_text::text;

/// The version of the JSON's structure: raised when a field changes
/// meaning or goes (new fields may come without it).
pub const JSON_VERSION: u32 = 1;

pub fn run(args: &Explain) -> Result<()> {
    let loaded = tracer_pipeline::load(&args.input)?;
    crate::report::warnings(&loaded, &args.options);
    crate::report::time_limit_unused(&loaded, &args.options);
    let pixel =
        tracer_pipeline::explain::explain(&loaded, &args.options, (args.x, args.y), args.sample)?;
    let text = if args.json {
        serde_json::to_string_pretty(&json(&pixel, (args.x, args.y)))? + "\n"
    } else {
        let name = args.input.name();
        text(&pixel, (args.x, args.y), &name.display().to_string())
    };
    console::stdout(&text)
}

/// The JSON of an explained pixel. Fixed: `version`, `pixel` ([X, Y]),
/// `rgb8`, `linear` and `ray` (with `origin`, `direction` and `hit`).
fn json(pixel: &ExplainedPixel, (x, y): (u32, u32)) -> serde_json::Value {
    let e = &pixel.explanation;
    let (integrator, ray, events) = match &e.trace {
        Trace::Whitted { ray } => ("whitted", ray, None),
        Trace::Path { ray, events } => ("path", ray, Some(events)),
    };
    let mut value = serde_json::json!({
        "version": JSON_VERSION,
        "pixel": [x, y],
        "size": [pixel.size.0, pixel.size.1],
        "rgb8": pixel.rgb8,
        "linear": pixel.linear,
        "encoding": {
            // As written (2.2), not as its f32 widened (2.200000047683716).
            "gamma": tracer_pipeline::as_written(pixel.encoding.gamma),
            "saturation": match pixel.encoding.saturation {
                Saturation::White => "white",
                Saturation::Clamp => "clamp",
            },
        },
        "integrator": integrator,
        "samples": e.samples,
        "sample": e.sample,
        "image_point": e.image_point,
        "lens_point": e.lens_point,
        "projection": e.projection,
        "sample_colour": e.colour,
        "ray": ray,
        "names": pixel.names,
    });
    if let Some(events) = events {
        value["events"] = serde_json::to_value(events).unwrap_or_default();
    }
    value
}
