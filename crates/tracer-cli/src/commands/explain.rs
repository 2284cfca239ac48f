//! `tracer explain SCENE X Y`: why a pixel has its colour, in the lab's
//! words and order (lab sections 1.2.3, 4 and 5): the primary ray, what it
//! met, each light's terms and shadow ray, the mirror and refracted rays,
//! then the sum, the saturation rule, gamma and the 8-bit value, which is
//! the rendered pixel's. In path mode, one sample's path: its vertices,
//! light and BSDF samples and their MIS weights. `--json` gives the same
//! as JSON (its structure documented in the book,
//! docs/src/reference/explain-json.md, versioned). The tree is kept within
//! `--max-events` (and `--light`), and written to stdout as it is
//! formatted, never held whole as text.

use crate::args::Explain;
use crate::console;
use crate::console::note;
use anyhow::Result;
use glam::{Vec2, Vec3};
use serde::Serialize;
use std::fmt;
use std::io;
use tracer_pipeline::explain::{Cut, ExplainedPixel, PathEvent, RayNode, Saturation, Trace};
use tracer_pipeline::explain_draw::Drawing;
use tracer_pipeline::explain_text::write_text;
use tracer_pipeline::output::{check_not_an_input, PendingOutput};
use tracer_pipeline::Error;

/// The version of the JSON's structure: raised when a field changes
/// meaning or goes (new fields may come without it).
pub const JSON_VERSION: u32 = 1;

pub fn run(args: &Explain) -> Result<()> {
    let loaded = tracer_pipeline::load(&args.input)?;
    crate::report::warnings(&loaded, &args.options);
    crate::report::time_limit_unused(&loaded, &args.options);
    let at = (args.x, args.y);
    // A wrong output is refused before any work.
    let drawn = match &args.draw {
        Some(path) => {
            check_not_an_input(path, &loaded.files_read).map_err(Error::from)?;
            Some(PendingOutput::create_8bit(path).map_err(Error::from)?)
        }
        None => None,
    };
    let pixel = tracer_pipeline::explain::explain_within(
        &loaded,
        &args.options,
        at,
        args.sample,
        args.limits,
    )?;
    if let Some(output) = drawn {
        let rendered = tracer_pipeline::render(&loaded, &args.options, &|_| {})?;
        let image = rendered.image.to_rgb8();
        let picture =
            super::explain_draw::draw(&image, &pixel.drawing).map_err(anyhow::Error::msg)?;
        let path = output.path().to_path_buf();
        output.write_image(&picture).map_err(Error::from)?;
        let k = super::explain_draw::enlargement(image.width(), image.height());
        let enlarged = if k > 1 {
            format!(", enlarged {k} times")
        } else {
            String::new()
        };
        note!(
            "the render with pixel ({}, {})'s rays drawn over it{enlarged} -> {}",
            at.0,
            at.1,
            path.display()
        );
    }
    if args.json {
        return console::stdout_streamed(|out| {
            let mut serializer =
                serde_json::Serializer::with_formatter(out, VisibleJson::default());
            json(&pixel, at).serialize(&mut serializer)?;
            serializer.into_inner().write_all(b"\n")
        });
    }
    let name = args.input.name().display().to_string();
    console::stdout_streamed(|out| {
        let mut text = IoText { out, error: None };
        match write_text(&mut text, &pixel, at, &name) {
            Ok(()) => Ok(()),
            Err(fmt::Error) => Err(text
                .error
                .unwrap_or_else(|| io::Error::other("the text could not be formatted"))),
        }
    })
}

/// An `io::Write` as the `fmt::Write` the text is written to, keeping its
/// error (a closed pipe ends the command quietly).
struct IoText<'a> {
    out: &'a mut dyn io::Write,
    error: Option<io::Error>,
}

impl fmt::Write for IoText<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.out.write_all(s.as_bytes()).map_err(|e| {
            self.error.get_or_insert(e);
            fmt::Error
        })
    }
}

/// The JSON of an explained pixel. Fixed: `version`, `pixel` ([X, Y]),
/// `rgb8`, `linear` and `ray` (with `origin`, `direction` and `hit`). Its
/// keys in alphabetical order, as they always were.
#[derive(Serialize)]
struct Json<'a> {
    #[serde(skip_serializing_if = "Option::is_none")]
    cut: Option<Cut>,
    drawing: &'a Drawing,
    encoding: JsonEncoding,
    #[serde(skip_serializing_if = "Option::is_none")]
    events: Option<&'a [PathEvent]>,
    image_point: Vec2,
    integrator: &'static str,
    lens_point: Vec2,
    linear: Vec3,
    names: &'a tracer_pipeline::explain::Names,
    #[serde(skip_serializing_if = "Option::is_none")]
    only_light: Option<usize>,
    pixel: [u32; 2],
    projection: [Vec3; 3],
    ray: &'a RayNode,
    rgb8: [u8; 3],
    sample: u32,
    sample_colour: Vec3,
    samples: u32,
    size: [u32; 2],
    version: u32,
}

#[derive(Serialize)]
struct JsonEncoding {
    /// As written (2.2), not as its f32 widened (2.200000047683716).
    gamma: f64,
    saturation: &'static str,
}

fn json(pixel: &ExplainedPixel, (x, y): (u32, u32)) -> Json<'_> {
    let e = &pixel.explanation;
    let (integrator, ray, events) = match &e.trace {
        Trace::Whitted { ray } => ("whitted", ray, None),
        Trace::Path { ray, events } => ("path", ray, Some(events.as_slice())),
    };
    Json {
        cut: e.cut,
        drawing: &pixel.drawing,
        encoding: JsonEncoding {
            gamma: tracer_pipeline::as_written(pixel.encoding.gamma),
            saturation: match pixel.encoding.saturation {
                Saturation::White => "white",
                Saturation::Clamp => "clamp",
            },
        },
        events,
        image_point: e.image_point,
        integrator,
        lens_point: e.lens_point,
        linear: pixel.linear,
        names: &pixel.names,
        only_light: e.only_light,
        pixel: [x, y],
        projection: e.projection,
        ray,
        rgb8: pixel.rgb8,
        sample: e.sample,
        sample_colour: e.colour,
        samples: e.samples,
        size: [pixel.size.0, pixel.size.1],
        version: JSON_VERSION,
    }
}

/// serde_json's pretty printing, with the control and bidirectional
/// characters it leaves as they are (DEL, C1 controls, U+202E, ...)
/// escaped as `\uXXXX` too (serde_json escapes those below U+0020): the
/// same strings, and none of them drives a terminal.
#[derive(Default)]
struct VisibleJson(serde_json::ser::PrettyFormatter<'static>);

impl serde_json::ser::Formatter for VisibleJson {
    fn write_string_fragment<W: ?Sized + io::Write>(
        &mut self,
        writer: &mut W,
        fragment: &str,
    ) -> io::Result<()> {
        let mut rest = fragment;
        while let Some((i, c)) = rest
            .char_indices()
            .find(|&(_, c)| scene_format::visible::is_hidden_control(c))
        {
            writer.write_all(&rest.as_bytes()[..i])?;
            // Every such character is in the Basic Multilingual Plane.
            write!(writer, "\\u{:04x}", c as u32)?;
            rest = &rest[i + c.len_utf8()..];
        }
        writer.write_all(rest.as_bytes())
    }

    fn begin_array<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_array(w)
    }

    fn end_array<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_array(w)
    }

    fn begin_array_value<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        self.0.begin_array_value(w, first)
    }

    fn end_array_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_array_value(w)
    }

    fn begin_object<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_object(w)
    }

    fn end_object<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object(w)
    }

    fn begin_object_key<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        self.0.begin_object_key(w, first)
    }

    fn begin_object_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_object_value(w)
    }

    fn end_object_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object_value(w)
    }
}
