//! `tracer explain --draw OUT.png`: the render with the pixel's ray tree
//! drawn over it, as the playground draws it: each ray from its origin to
//! its end where the image sees it (the pipeline's `Drawing`, projected by
//! the core's camera), the hits ringed, shadow rays solid when clear and
//! dashed red when blocked with their blocker crossed and named, the lights
//! marked, and an arrow where a ray leaves the image; a legend in a strip
//! below the picture, so nothing of the picture is hidden by it.

use glam::DVec2;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use tracer_pipeline::explain_draw::{Drawing, DrawnKind, DrawnRay};

/// The font the labels are written in: DejaVu Sans, compiled in.
const FONT: &str = "sans-serif";

/// The colours: few, each a kind of ray, bright over dark and light
/// pictures alike (each line has a black halo).
pub const PRIMARY: RGBColor = RGBColor(255, 214, 0);
pub const REFLECTED: RGBColor = RGBColor(0, 190, 255);
pub const REFRACTED: RGBColor = RGBColor(90, 230, 110);
pub const SHADOW: RGBColor = RGBColor(255, 255, 255);
pub const BLOCKED: RGBColor = RGBColor(255, 40, 40);
pub const BOUNCE: RGBColor = RGBColor(255, 140, 0);
pub const LIGHT: RGBColor = RGBColor(255, 245, 150);
const HALO: RGBColor = RGBColor(0, 0, 0);
const STRIP: RGBColor = RGBColor(40, 40, 40);

/// The colour of a ray.
pub fn colour(ray: &DrawnRay) -> RGBColor {
    match ray.kind {
        DrawnKind::Primary => PRIMARY,
        DrawnKind::Reflected => REFLECTED,
        DrawnKind::Refracted => REFRACTED,
        DrawnKind::Shadow if ray.blocked => BLOCKED,
        DrawnKind::Shadow => SHADOW,
        DrawnKind::Bounce => BOUNCE,
    }
}

/// Sizes in pixels of the drawing's strokes, marks and text: the same on
/// the image whatever its size, up to a laptop screen's, then growing.
struct Sizes {
    line: u32,
    ring: i32,
    text: f64,
}

impl Sizes {
    fn of(size: (u32, u32)) -> Sizes {
        let scale = (f64::from(size.0.max(size.1)) / 800.0).max(1.0);
        Sizes {
            line: (2.0 * scale).round() as u32,
            ring: (5.0 * scale).round() as i32,
            text: 13.0 * scale,
        }
    }
}

/// The picture at least this wide or high, enlarged by a whole factor
/// when smaller (a 64x64 test scene's marks would hide it).
const LEAST_SIDE: u32 = 480;

/// How many times a `w` x `h` picture is enlarged (each pixel a square):
/// the least whole factor that brings its longer side to `LEAST_SIDE`.
pub fn enlargement(w: u32, h: u32) -> u32 {
    LEAST_SIDE.div_ceil(w.max(h).max(1)).max(1)
}

/// `picture` (the render, RGB) with `drawing` over it and a legend below,
/// enlarged [`enlargement`] times.
pub fn draw(picture: &image::RgbImage, drawing: &Drawing) -> Result<image::RgbImage, String> {
    register_embedded_font();
    let k = enlargement(picture.width(), picture.height());
    let picture = image::imageops::resize(
        picture,
        picture.width() * k,
        picture.height() * k,
        image::imageops::FilterType::Nearest,
    );
    let drawing = &scaled(drawing, f64::from(k));
    let (w, h) = picture.dimensions();
    let sizes = Sizes::of((w, h));
    let legend = legend(drawing);
    // The strip is at least wide enough for a few items a line.
    let width = w.max(360);
    let rows = legend_rows(&legend, width, &sizes);
    let line_height = (sizes.text * 1.6).ceil() as u32;
    let strip = line_height * (rows.len() as u32) + line_height / 2;
    let mut out =
        image::RgbImage::from_pixel(width, h + strip, image::Rgb([STRIP.0, STRIP.1, STRIP.2]));
    image::imageops::replace(&mut out, &picture, 0, 0);
    {
        let backend = BitMapBackend::with_buffer(out.as_mut(), (width, h + strip));
        let root = backend.into_drawing_area();
        let fail = |e: DrawingAreaErrorKind<_>| format!("cannot draw the rays: {e}");
        let image_area = root.clone().shrink((0, 0), (w, h));
        for ray in &drawing.rays {
            draw_ray(&image_area, ray, &sizes).map_err(fail)?;
        }
        for light in &drawing.lights {
            if let Some(at) = light.seen_at {
                draw_light(&image_area, at, &sizes).map_err(fail)?;
            }
        }
        // The hits over the lines that reach them, and the blockers over
        // all.
        for ray in drawing.rays.iter().filter(|r| r.kind != DrawnKind::Shadow) {
            if let Some(at) = ray.image.and_then(|s| s.end_seen) {
                ring(&image_area, at, colour(ray), &sizes).map_err(fail)?;
            }
        }
        for blocker in drawing.rays.iter().filter_map(|r| r.blocked_by.as_ref()) {
            if let Some(at) = blocker.seen_at {
                cross(&image_area, at, &sizes).map_err(fail)?;
                label(&image_area, at, &blocker.name, &sizes).map_err(fail)?;
            }
        }
        let strip_area = root.clone().shrink((0, h), (width, strip));
        draw_legend(&strip_area, &rows, line_height, &sizes).map_err(fail)?;
        root.present().map_err(fail)?;
    }
    Ok(out)
}

/// `drawing` with its image coordinates times `k`.
fn scaled(drawing: &Drawing, k: f64) -> Drawing {
    let mut drawing = drawing.clone();
    for ray in &mut drawing.rays {
        if let Some(s) = &mut ray.image {
            s.from *= k;
            s.to *= k;
            s.end_seen = s.end_seen.map(|p| p * k);
        }
        if let Some(b) = &mut ray.blocked_by {
            b.seen_at = b.seen_at.map(|p| p * k);
        }
    }
    for light in &mut drawing.lights {
        light.seen_at = light.seen_at.map(|p| p * k);
    }
    drawing
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type Drawn<'a> = Result<(), DrawingAreaErrorKind<<BitMapBackend<'a> as DrawingBackend>::ErrorType>>;

/// The pixel a point of the image is in.
fn pixel(p: DVec2) -> (i32, i32) {
    (p.x.floor() as i32, p.y.floor() as i32)
}

fn register_embedded_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // Compiled in: it fails only if the bytes were bad.
        let _ = register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

/// One ray: its line (dashed when blocked, with a black halo), and an
/// arrow where it leaves the image.
fn draw_ray<'a>(area: &Area<'a>, ray: &DrawnRay, sizes: &Sizes) -> Drawn<'a> {
    let Some(segment) = ray.image else {
        return Ok(());
    };
    let colour = colour(ray);
    let points = [pixel(segment.from), pixel(segment.to)];
    let width = if ray.kind == DrawnKind::Shadow {
        sizes.line.saturating_sub(1).max(1)
    } else {
        sizes.line
    };
    let halo = HALO.stroke_width(width + 2);
    let style = colour.stroke_width(width);
    if ray.blocked {
        let (dash, gap) = (6 * width, 4 * width);
        area.draw(&DashedPathElement::new(points, dash, gap, halo))?;
        area.draw(&DashedPathElement::new(points, dash, gap, style))?;
    } else {
        area.draw(&PathElement::new(points, halo))?;
        area.draw(&PathElement::new(points, style))?;
    }
    if segment.leaves {
        arrow(area, segment.from, segment.to, colour, sizes)?;
    }
    Ok(())
}

/// A filled triangle at `to` pointing away from `from`: the ray goes on
/// out of the image there.
fn arrow<'a>(
    area: &Area<'a>,
    from: DVec2,
    to: DVec2,
    colour: RGBColor,
    sizes: &Sizes,
) -> Drawn<'a> {
    let along = (to - from).try_normalize().unwrap_or(DVec2::X);
    let across = along.perp();
    let size = f64::from(sizes.ring) * 2.6;
    let tip = to;
    let base = to - along * size;
    let corners = [tip, base + across * size * 0.5, base - across * size * 0.5].map(pixel);
    area.draw(&Polygon::new(corners.to_vec(), colour.filled()))?;
    area.draw(&PathElement::new(
        [corners[0], corners[1], corners[2], corners[0]],
        HALO.stroke_width(1),
    ))
}

/// A ring round a hit.
fn ring<'a>(area: &Area<'a>, at: DVec2, colour: RGBColor, sizes: &Sizes) -> Drawn<'a> {
    let c = pixel(at);
    area.draw(&Circle::new(
        c,
        sizes.ring + 1,
        HALO.stroke_width(sizes.line + 2),
    ))?;
    area.draw(&Circle::new(
        c,
        sizes.ring + 1,
        colour.stroke_width(sizes.line),
    ))?;
    area.draw(&Circle::new(c, 1, colour.filled()))
}

/// A light: a small sun.
fn draw_light<'a>(area: &Area<'a>, at: DVec2, sizes: &Sizes) -> Drawn<'a> {
    let c = pixel(at);
    let r = sizes.ring;
    for k in 0..8 {
        let angle = std::f64::consts::FRAC_PI_4 * f64::from(k);
        let (s, co) = angle.sin_cos();
        let end = (
            c.0 + (co * f64::from(2 * r)) as i32,
            c.1 + (s * f64::from(2 * r)) as i32,
        );
        area.draw(&PathElement::new(
            [c, end],
            HALO.stroke_width(sizes.line + 2),
        ))?;
        area.draw(&PathElement::new([c, end], LIGHT.stroke_width(sizes.line)))?;
    }
    area.draw(&Circle::new(c, r, LIGHT.filled()))?;
    area.draw(&Circle::new(c, r, HALO.stroke_width(1)))
}

/// An X where a shadow ray is blocked.
fn cross<'a>(area: &Area<'a>, at: DVec2, sizes: &Sizes) -> Drawn<'a> {
    let (x, y) = pixel(at);
    let r = sizes.ring;
    for (a, b) in [
        ((x - r, y - r), (x + r, y + r)),
        ((x - r, y + r), (x + r, y - r)),
    ] {
        area.draw(&PathElement::new([a, b], HALO.stroke_width(sizes.line + 3)))?;
        area.draw(&PathElement::new(
            [a, b],
            BLOCKED.stroke_width(sizes.line + 1),
        ))?;
    }
    Ok(())
}

/// A name beside a mark, white on a thin black outline.
fn label<'a>(area: &Area<'a>, at: DVec2, text: &str, sizes: &Sizes) -> Drawn<'a> {
    // Above and right of the mark, so that it hides neither the mark nor
    // a hit ringed beside it.
    let (x, y) = pixel(at);
    let (x, y) = (x + sizes.ring, y - sizes.ring - (sizes.text * 1.2) as i32);
    let font = |c: &RGBColor| (FONT, sizes.text).into_font().color(c);
    for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
        area.draw(&Text::new(text.to_string(), (x + dx, y + dy), font(&HALO)))?;
    }
    area.draw(&Text::new(text.to_string(), (x, y), font(&WHITE)))
}

/// One item of the legend: its mark and its words.
#[derive(Debug, Clone)]
struct Item {
    mark: Mark,
    words: String,
}

#[derive(Debug, Clone, Copy)]
enum Mark {
    Line(RGBColor),
    Dashed(RGBColor),
    Ring,
    Light,
    Arrow,
    Text,
}

/// What the drawing shows, in the order a student meets it: only the kinds
/// of ray present, then the blockers by name.
fn legend(drawing: &Drawing) -> Vec<Item> {
    let has =
        |f: &dyn Fn(&DrawnRay) -> bool| drawing.rays.iter().any(|r| r.image.is_some() && f(r));
    let mut items = vec![Item {
        mark: Mark::Text,
        words: format!("pixel ({}, {}):", drawing.pixel[0], drawing.pixel[1]),
    }];
    let kinds = [
        (DrawnKind::Primary, PRIMARY, "primary ray"),
        (DrawnKind::Reflected, REFLECTED, "mirror ray"),
        (DrawnKind::Refracted, REFRACTED, "refracted ray"),
        (DrawnKind::Bounce, BOUNCE, "path's bounce"),
    ];
    for (kind, colour, words) in kinds {
        if has(&|r| r.kind == kind) {
            items.push(Item {
                mark: Mark::Line(colour),
                words: words.to_string(),
            });
        }
    }
    if drawing
        .rays
        .iter()
        .any(|r| r.kind != DrawnKind::Shadow && r.image.is_some_and(|s| s.end_seen.is_some()))
    {
        items.push(Item {
            mark: Mark::Ring,
            words: "hit".to_string(),
        });
    }
    if has(&|r| r.kind == DrawnKind::Shadow && !r.blocked) {
        items.push(Item {
            mark: Mark::Line(SHADOW),
            words: "shadow ray, clear".to_string(),
        });
    }
    if has(&|r| r.blocked) {
        items.push(Item {
            mark: Mark::Dashed(BLOCKED),
            words: "shadow ray, blocked".to_string(),
        });
    }
    if drawing.lights.iter().any(|l| l.seen_at.is_some()) {
        items.push(Item {
            mark: Mark::Light,
            words: "light".to_string(),
        });
    }
    if has(&|r| r.image.is_some_and(|s| s.leaves)) {
        items.push(Item {
            mark: Mark::Arrow,
            words: "leaves the image".to_string(),
        });
    }
    for ray in drawing.rays.iter().filter(|r| r.blocked) {
        let to = ray
            .light
            .map_or("a light".to_string(), |l| format!("lights[{l}]"));
        let by = ray
            .blocked_by
            .as_ref()
            .map_or("something".to_string(), |b| b.name.clone());
        items.push(Item {
            mark: Mark::Text,
            words: format!("ray to {to} blocked by {by}"),
        });
    }
    items
}

const SWATCH: i32 = 26;

/// The legend's items laid out in rows that fit `width`.
fn legend_rows(items: &[Item], width: u32, sizes: &Sizes) -> Vec<Vec<Item>> {
    let mut rows: Vec<Vec<Item>> = vec![Vec::new()];
    let mut x = 8;
    for item in items {
        let w = item_width(item, sizes);
        if x + w > width as i32 && !rows.last().is_some_and(Vec::is_empty) {
            rows.push(Vec::new());
            x = 8;
        }
        rows.last_mut().expect("a row").push(item.clone());
        x += w;
    }
    rows
}

/// An item's width: its mark, its words and a gap.
fn item_width(item: &Item, sizes: &Sizes) -> i32 {
    mark_width(item) + words_width(&item.words, sizes) + 14
}

fn mark_width(item: &Item) -> i32 {
    match item.mark {
        Mark::Text => 0,
        _ => SWATCH + 6,
    }
}

/// The width of `words` as written (about 0.55 of the size a character
/// should the font not say).
fn words_width(words: &str, sizes: &Sizes) -> i32 {
    let font: FontDesc = (FONT, sizes.text).into_font();
    match font.box_size(words) {
        Ok((w, _)) => w as i32,
        Err(_) => (words.chars().count() as f64 * sizes.text * 0.55) as i32,
    }
}

fn draw_legend<'a>(
    area: &Area<'a>,
    rows: &[Vec<Item>],
    line_height: u32,
    sizes: &Sizes,
) -> Drawn<'a> {
    let font = (FONT, sizes.text).into_font().color(&WHITE);
    for (r, row) in rows.iter().enumerate() {
        let y = (line_height / 2) as i32 + r as i32 * line_height as i32 + line_height as i32 / 2;
        let mut x = 8;
        for item in row {
            let mid = (x + SWATCH / 2, y);
            match item.mark {
                Mark::Line(c) => {
                    area.draw(&PathElement::new(
                        [(x, y), (x + SWATCH, y)],
                        c.stroke_width(sizes.line),
                    ))?;
                }
                Mark::Dashed(c) => {
                    let dash = DashedPathElement::new(
                        [(x, y), (x + SWATCH, y)],
                        6,
                        4,
                        c.stroke_width(sizes.line),
                    );
                    area.draw(&dash)?;
                }
                Mark::Ring => {
                    area.draw(&Circle::new(
                        mid,
                        sizes.ring + 1,
                        WHITE.stroke_width(sizes.line),
                    ))?;
                }
                Mark::Light => {
                    draw_light(area, DVec2::new(f64::from(mid.0), f64::from(mid.1)), sizes)?
                }
                Mark::Arrow => {
                    let (to, from) = (
                        DVec2::new(f64::from(x + SWATCH), f64::from(y)),
                        DVec2::new(f64::from(x), f64::from(y)),
                    );
                    arrow(area, from, to, WHITE, sizes)?;
                }
                Mark::Text => {}
            }
            let top = y - (sizes.text * 0.55) as i32;
            let words_at = (x + mark_width(item), top);
            area.draw(&Text::new(item.words.clone(), words_at, font.clone()))?;
            x += item_width(item, sizes);
        }
    }
    Ok(())
}
