//! The raster a canvas scene is drawn on: canvas coordinates to pixels
//! (+x to the LEFT, +y up), lines 2 pixels thick, circles and polygons,
//! every shape decided by testing pixel centres.

use glam::{Vec2, Vec3};
use tracer_core::image::LinearImage;

/// Lines are 2 pixels thick, as in the template.
pub const LINE_WIDTH: f32 = 2.0;

/// A raster image drawn on with canvas coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Canvas {
    pub image: LinearImage,
}

impl Canvas {
    pub fn new(width: u32, height: u32, background: Vec3) -> Self {
        let mut image = LinearImage::new(width, height);
        image.pixels.fill(background);
        Canvas { image }
    }

    fn size(&self) -> Vec2 {
        Vec2::new(self.image.width as f32, self.image.height as f32)
    }

    /// The template's mapping to continuous pixel coordinates:
    /// column `W - (x + 1) / 2 * W`, row `H - (y + 1) / 2 * H`.
    pub fn to_pixel(&self, p: Vec2) -> Vec2 {
        let size = self.size();
        size - (p + Vec2::ONE) / 2.0 * size
    }

    /// The pixel (column, row) a point falls in, truncated as the template does;
    /// it may lie outside the image.
    pub fn pixel_of(&self, p: Vec2) -> (i64, i64) {
        let q = self.to_pixel(p).floor();
        (q.x as i64, q.y as i64)
    }

    /// The template's `drawCircle` radius: `r / 2 * W` pixels.
    pub fn radius_in_pixels(&self, r: f32) -> f32 {
        r / 2.0 * self.size().x
    }

    /// Sets every pixel in the box (continuous pixel coordinates, grown by
    /// the line width) whose centre passes `inside`.
    fn paint(&mut self, lo: Vec2, hi: Vec2, colour: Vec3, inside: impl Fn(Vec2) -> bool) {
        let size = self.size();
        let lo = (lo - Vec2::splat(LINE_WIDTH)).max(Vec2::ZERO).floor();
        let hi = (hi + Vec2::splat(LINE_WIDTH)).min(size).ceil();
        if !(lo.x < hi.x && lo.y < hi.y) {
            return;
        }
        let width = self.image.width as usize;
        for j in lo.y as usize..hi.y as usize {
            for i in lo.x as usize..hi.x as usize {
                if inside(Vec2::new(i as f32 + 0.5, j as f32 + 0.5)) {
                    self.image.pixels[j * width + i] = colour;
                }
            }
        }
    }

    /// A line 2 pixels thick: pixel centres within the band [-1, 1) across
    /// the line, from 1 pixel before its start to 1 pixel past its end (so
    /// the outline of a square has closed corners).
    pub fn draw_line(&mut self, a: Vec2, b: Vec2, colour: Vec3) {
        let (a, b) = (self.to_pixel(a), self.to_pixel(b));
        // One order for both directions, so the half-open band is the same.
        let (a, b) = if (a.x, a.y) <= (b.x, b.y) {
            (a, b)
        } else {
            (b, a)
        };
        let length = a.distance(b);
        let along = if length > 0.0 {
            (b - a) / length
        } else {
            Vec2::X
        };
        let across = along.perp();
        let half = LINE_WIDTH / 2.0;
        self.paint(a.min(b), a.max(b), colour, |c| {
            let s = (c - a).dot(along);
            let d = (c - a).dot(across);
            (-half..length + half).contains(&s) && (-half..half).contains(&d)
        });
    }

    /// A circle of radius `r` canvas units (`r / 2 * W` pixels, round in
    /// pixels even on a canvas that is not square, as in the template):
    /// a 2-pixel ring centred on the radius, or the filled disc.
    pub fn draw_circle(&mut self, centre: Vec2, r: f32, colour: Vec3, fill: bool) {
        let c = self.to_pixel(centre);
        let radius = self.radius_in_pixels(r).abs();
        let half = LINE_WIDTH / 2.0;
        let reach = Vec2::splat(radius + half);
        self.paint(c - reach, c + reach, colour, |p| {
            let d = p.distance(c);
            if fill {
                d < radius
            } else {
                (radius - half..radius + half).contains(&d)
            }
        });
    }

    /// A closed polygon: its edges as lines, or its inside (even-odd rule).
    pub fn draw_polygon(&mut self, points: &[Vec2], colour: Vec3, fill: bool) {
        if points.is_empty() {
            return;
        }
        if !fill {
            for (k, &a) in points.iter().enumerate() {
                self.draw_line(a, points[(k + 1) % points.len()], colour);
            }
            return;
        }
        let pixels: Vec<Vec2> = points.iter().map(|&p| self.to_pixel(p)).collect();
        let lo = pixels.iter().fold(Vec2::INFINITY, |m, &p| m.min(p));
        let hi = pixels.iter().fold(Vec2::NEG_INFINITY, |m, &p| m.max(p));
        self.paint(lo, hi, colour, |c| inside_even_odd(&pixels, c));
    }
}

/// Whether `c` is inside the polygon by the even-odd rule.
fn inside_even_odd(polygon: &[Vec2], c: Vec2) -> bool {
    let mut inside = false;
    for (k, &a) in polygon.iter().enumerate() {
        let b = polygon[(k + 1) % polygon.len()];
        if (a.y > c.y) != (b.y > c.y) {
            let x = a.x + (c.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if c.x < x {
                inside = !inside;
            }
        }
    }
    inside
}
