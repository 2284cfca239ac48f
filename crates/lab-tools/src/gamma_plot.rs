//! The lab's `draw-gamma.m` figure, drawn with plotters into an image: the
//! measured (normalised) display curve, the fitted `y = x^gamma`, the
//! correcting `y = x^(1/gamma)` and, when measured, the display after
//! correction, against the straight line it should approach.

use crate::gamma_fit::GammaFit;
use crate::measurements::{normalised_points, Measurement};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::sync::Once;

/// The font family plotters draws with; registered from the embedded DejaVu
/// Sans, so the plot needs no font installed on the machine.
const FONT: &str = "sans-serif";

/// The plot's size in pixels, as `tracer gamma fit --plot` draws it.
pub const DEFAULT_SIZE: (u32, u32) = (800, 600);

/// The plotting library failed to draw (plotters' own message inside).
#[derive(Debug, thiserror::Error)]
#[error("cannot draw the gamma plot: {0}")]
pub struct PlotError(String);

fn register_embedded_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is compiled in; it can only fail if the bytes were bad.
        let _ = register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

/// The colour of the y = x line: dark grey, a touch of blue so that the
/// anti-aliased text (pure greys) never has it.
const LINEAR: RGBColor = RGBColor(80, 80, 100);

/// Samples of `f` over [0, 1] for a smooth curve.
fn curve(f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    const SAMPLES: usize = 200;
    (0..=SAMPLES)
        .map(|k| {
            let x = k as f64 / SAMPLES as f64;
            (x, f(x))
        })
        .collect()
}

/// The measured points joined in order of level: the measured curve.
fn by_level(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    sorted
}

/// Draws the plot as an RGB image of `width` x `height` pixels.
pub fn plot_gamma(
    rows: &[Measurement],
    fit: &GammaFit,
    width: u32,
    height: u32,
) -> Result<image::RgbImage, PlotError> {
    register_embedded_font();
    let mut buffer = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        draw(&root, rows, fit).map_err(|e| PlotError(e.to_string()))?;
        root.present().map_err(|e| PlotError(e.to_string()))?;
    }
    image::RgbImage::from_raw(width, height, buffer)
        .ok_or_else(|| PlotError("the plot buffer has the wrong size".to_string()))
}

type DrawResult = Result<(), Box<dyn std::error::Error>>;

fn draw(
    root: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    rows: &[Measurement],
    fit: &GammaFit,
) -> DrawResult {
    let g = fit.gamma;
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(root)
        .caption(format!("Display gamma: {g:.2}"), (FONT, 28))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d(0f64..1f64, 0f64..1.05f64)?;
    chart
        .configure_mesh()
        .x_desc("input value x (colour level)")
        .y_desc("normalised luminance y")
        .axis_desc_style((FONT, 18))
        .label_style((FONT, 15))
        .draw()?;

    let red = RGBColor(210, 40, 40);
    chart
        .draw_series(LineSeries::new(curve(|x| x.powf(g)), red.stroke_width(2)))?
        .label(format!("fit: y = x^{g:.2}"))
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], red.stroke_width(2)));

    let green = RGBColor(30, 150, 60);
    chart
        .draw_series(LineSeries::new(
            curve(|x| x.powf(1.0 / g)),
            green.stroke_width(2),
        ))?
        .label(format!("correction: y = x^(1/{g:.2})"))
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], green.stroke_width(2)));

    let blue = RGBColor(30, 80, 200);
    let measured = normalised_points(rows, |m| Some(m.luminance));
    chart.draw_series(LineSeries::new(by_level(&measured), blue.stroke_width(1)))?;
    chart
        .draw_series(measured.iter().map(|&p| Circle::new(p, 5, blue.filled())))?
        .label("measured, joined in order")
        // The legend shows the joining line through the marker, as drawn.
        .legend(move |(x, y)| {
            EmptyElement::at((x + 10, y))
                + PathElement::new([(-10, 0), (10, 0)], blue.stroke_width(1))
                + Circle::new((0, 0), 5, blue.filled())
        });

    let purple = RGBColor(140, 40, 170);
    let corrected = normalised_points(rows, |m| m.corrected);
    if !corrected.is_empty() {
        // Markers only: the corrected points should lie on y = x, and a
        // line joining them would hide it.
        chart
            .draw_series(
                corrected
                    .iter()
                    .map(|&p| TriangleMarker::new(p, 7, purple.filled())),
            )?
            .label("measured after correction")
            .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 7, purple.filled()));
    }

    // Drawn last, over the others: the line the corrected points should
    // lie on, in a colour of its own (no curve or marker is grey).
    chart
        .draw_series(DashedLineSeries::new(
            curve(|x| x),
            6,
            4,
            LINEAR.stroke_width(2),
        ))?
        .label("linear: y = x")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], LINEAR.stroke_width(2)));

    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT, 16))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gamma_fit::fit_measurements;
    use crate::measurements::parse_measurements;

    fn sample() -> Vec<Measurement> {
        parse_measurements("0,0.4,0.4\n0.25,10.7,63\n0.5,51,126\n0.75,129,187\n1,250,249\n")
            .unwrap()
    }

    fn has_colour(img: &image::RgbImage, rgb: [u8; 3]) -> bool {
        img.pixels().any(|p| p.0 == rgb)
    }

    #[test]
    fn the_plot_shows_every_series_and_some_text() {
        let rows = sample();
        let fit = fit_measurements(&rows).unwrap();
        let img = plot_gamma(&rows, &fit, 800, 600).unwrap();
        assert_eq!(img.dimensions(), (800, 600));
        for colour in [[210, 40, 40], [30, 150, 60], [30, 80, 200], [140, 40, 170]] {
            assert!(has_colour(&img, colour), "{colour:?} missing");
        }
        // The text is anti-aliased: grey levels between black and white
        // appear only where glyphs (or the legend's box) are drawn.
        let greys = img
            .pixels()
            .filter(|p| p.0[0] == p.0[1] && p.0[1] == p.0[2] && (30..220).contains(&p.0[0]))
            .count();
        assert!(greys > 200, "{greys} grey pixels: no text?");
    }

    #[test]
    fn the_linear_line_shows_in_its_own_colour_between_the_corrected_points() {
        let rows = sample();
        let fit = fit_measurements(&rows).unwrap();
        let img = plot_gamma(&rows, &fit, 800, 600).unwrap();
        // x = 0.375 lies halfway between the corrected points at 0.25 and
        // 0.5; the plot area spans pixels 80 to 780 (margin 20, labels 60),
        // so its columns are near 80 + 0.375 * 700 = 342.
        let columns = 336..350;
        let colour_in_columns = |rgb: [u8; 3]| {
            columns
                .clone()
                .any(|x| (0..600).any(|y| img.get_pixel(x, y).0 == rgb))
        };
        assert!(colour_in_columns(LINEAR.rgb().into()), "y = x not drawn");
        assert!(
            !colour_in_columns([140, 40, 170]),
            "a corrected-points line covers y = x"
        );
    }

    #[test]
    fn without_a_corrected_column_its_series_is_left_out() {
        let rows: Vec<Measurement> = sample()
            .into_iter()
            .map(|m| Measurement {
                corrected: None,
                ..m
            })
            .collect();
        let fit = fit_measurements(&rows).unwrap();
        let img = plot_gamma(&rows, &fit, 640, 480).unwrap();
        assert!(!has_colour(&img, [140, 40, 170]));
    }
}
