//! The book's denoising figures (`cargo xtask denoise-figures`): how a
//! figure is laid out, and that the committed ones show each scene's
//! render at its size, the denoised panel closer to the reference than the
//! noisy one and the reference as the EXR. Cheap: no render, no OIDN.

use image::{Rgb, RgbImage};
use xtask::bench::denoise_figure::{self as figure, Panel};

fn panel(w: u32, h: u32, value: u8) -> Panel {
    Panel {
        image: RgbImage::from_pixel(w, h, Rgb([value, 0, 255 - value])),
        title: "title".into(),
        note: "RMSE 0.0000".into(),
    }
}

#[test]
fn a_figure_holds_its_three_panels_unchanged_side_by_side() {
    let (w, h) = (40, 30);
    let out = figure::compose(&[panel(w, h, 10), panel(w, h, 20), panel(w, h, 30)]).unwrap();
    assert_eq!(out.dimensions(), figure::figure_size((w, h)));
    for (i, value) in [(0, 10), (1, 20), (2, 30)] {
        let (x0, y0) = figure::panel_origin(i, w);
        for (x, y) in [
            (0, 0),
            (w - 1, 0),
            (0, h - 1),
            (w - 1, h - 1),
            (w / 2, h / 2),
        ] {
            assert_eq!(out.get_pixel(x0 + x, y0 + y), &Rgb([value, 0, 255 - value]));
        }
    }
    // The labels are written below the panels.
    let strip_y = figure::GAP + h;
    let written = (strip_y..out.height())
        .flat_map(|y| (0..out.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| out.get_pixel(x, y) != &Rgb([255, 255, 255]))
        .count();
    assert!(written > 20, "no label below the panels");
}

#[test]
fn panels_of_different_sizes_are_refused() {
    assert!(figure::compose(&[panel(4, 4, 0), panel(4, 4, 0), panel(4, 5, 0)]).is_err());
}

fn crop(image: &RgbImage, i: u32, (w, h): (u32, u32)) -> RgbImage {
    let (x, y) = figure::panel_origin(i, w);
    image::imageops::crop_imm(image, x, y, w, h).to_image()
}

/// The RMSE of two 8-bit images, in 0..=255.
fn rmse8(a: &RgbImage, b: &RgbImage) -> f64 {
    let sum: f64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).powi(2))
        .sum();
    (sum / a.as_raw().len() as f64).sqrt()
}

#[test]
fn the_committed_figures_show_denoising_closer_to_the_reference() {
    let root = xtask::workspace_root();
    for bench in figure::SCENES {
        let path = figure::path(&root, &bench);
        let shown = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (cargo xtask denoise-figures)", path.display()))
            .into_rgb8();
        let reference = image::open(root.join(bench.reference))
            .unwrap()
            .into_rgb32f();
        let k = figure::enlargement(reference.width());
        let size = (reference.width() * k, reference.height() * k);
        assert_eq!(
            shown.dimensions(),
            figure::figure_size(size),
            "{}: not three panels of the reference's size",
            path.display()
        );
        let [noisy, denoised, shown_reference] = [0, 1, 2].map(|i| crop(&shown, i, size));
        let (noisy_error, denoised_error) = (
            rmse8(&noisy, &shown_reference),
            rmse8(&denoised, &shown_reference),
        );
        assert!(
            denoised_error < noisy_error / 2.0,
            "{}: the denoised panel is {denoised_error:.2} from the reference, the noisy one {noisy_error:.2}",
            path.display()
        );
        // The reference panel is the EXR as the scene's PNG would show it:
        // its file's gamma and saturation rule (each channel clamped, path
        // mode's default; or the lab's: a pixel with a channel above 1 is
        // white), written here as the formula, not the pipeline's code.
        let scene: toml::Table =
            toml::from_str(&std::fs::read_to_string(root.join(bench.scene)).unwrap()).unwrap();
        let render = scene.get("render").and_then(|r| r.as_table());
        let key = |k: &str| render.and_then(|r| r.get(k));
        let gamma = key("gamma").and_then(|g| g.as_float()).unwrap_or(2.2) as f32;
        let clamp = match key("saturation").and_then(|s| s.as_str()) {
            Some(rule) => rule == "clamp",
            None => key("integrator").and_then(|i| i.as_str()) == Some("path"),
        };
        let encode = |rgb: [f32; 3]| {
            let white = !clamp && rgb.iter().any(|&c| c > 1.0);
            rgb.map(|c| {
                let c = if white { 1.0 } else { c.clamp(0.0, 1.0) };
                (c.powf(1.0 / gamma) * 255.0) as u8
            })
        };
        let mut off = 0;
        for (x, y, p) in shown_reference.enumerate_pixels() {
            let want = encode(reference.get_pixel(x / k, y / k).0);
            off += usize::from(p.0.iter().zip(want).any(|(&a, b)| a.abs_diff(b) > 1));
        }
        assert_eq!(
            off,
            0,
            "{}: the reference panel is not the EXR",
            path.display()
        );
    }
}
