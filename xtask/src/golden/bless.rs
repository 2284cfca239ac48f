//! `cargo xtask golden --bless`: the renders become the goldens, and what
//! changed is said image by image.

use super::cases::{all_cases, select, Case};
use super::check::{golden_path, read_golden};
use super::compare::{compare, Comparison, SizeMismatch, Tolerance};
use anyhow::{Context, Result};
use image::RgbImage;
use rayon::prelude::*;
use std::path::Path;
use tracer_pipeline::output;

/// What blessing did to one golden.
#[derive(Debug, Clone, PartialEq)]
pub enum Blessed {
    New {
        name: String,
        size: (u32, u32),
    },
    /// Rewritten; `change` counts every pixel that is not identical.
    Changed {
        name: String,
        change: Comparison,
    },
    Resized {
        name: String,
        change: SizeMismatch,
    },
    /// The old golden could not be read; it was replaced.
    Unreadable {
        name: String,
        error: String,
    },
    Unchanged {
        name: String,
    },
}

impl std::fmt::Display for Blessed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Blessed::New { name, size: (w, h) } => write!(f, "new        {name} ({w}x{h})"),
            Blessed::Changed { name, change: c } => write!(
                f,
                "changed    {name}: {} of {} pixels not identical ({:.3} %; the check counts only those beyond tolerance), max diff {}, mean diff {:.4}",
                c.differing,
                c.pixels,
                c.differing_percent(),
                c.max_diff,
                c.mean_diff
            ),
            Blessed::Resized { name, change } => write!(f, "changed    {name}: {change}"),
            Blessed::Unreadable { name, error } => {
                write!(
                    f,
                    "replaced   {name}: the old golden was unreadable ({error})"
                )
            }
            Blessed::Unchanged { name } => write!(f, "unchanged  {name}"),
        }
    }
}

/// Renders the cases and makes each the golden in `golden_dir`; a golden whose
/// pixels are already identical is left as it is. Nothing is written unless
/// every render succeeded.
pub fn bless(cases: &[Case], golden_dir: &Path) -> Result<Vec<Blessed>> {
    let renders: Vec<(&Case, RgbImage)> = cases
        .par_iter()
        .map(|case| {
            let image = (case.render)().with_context(|| format!("{}: render failed", case.name))?;
            Ok((case, image))
        })
        .collect::<Result<_>>()?;
    std::fs::create_dir_all(golden_dir)
        .with_context(|| format!("cannot create {}", golden_dir.display()))?;
    renders
        .iter()
        .map(|(case, image)| bless_one(&case.name, image, golden_dir))
        .collect()
}

fn bless_one(name: &str, image: &RgbImage, golden_dir: &Path) -> Result<Blessed> {
    let path = golden_path(golden_dir, name);
    let exact = Tolerance {
        channel: 0,
        max_differing_percent: 0.0,
    };
    let name = name.to_string();
    let blessed = match read_golden(&path) {
        Ok(None) => Blessed::New {
            name,
            size: image.dimensions(),
        },
        Err(e) => Blessed::Unreadable {
            name,
            error: format!("{e:#}"),
        },
        Ok(Some(old)) => match compare(&old, image, &exact) {
            Ok(c) if c.differing == 0 => return Ok(Blessed::Unchanged { name }),
            Ok(change) => Blessed::Changed { name, change },
            Err(change) => Blessed::Resized { name, change },
        },
    };
    output::write_image(image, &path)?;
    Ok(blessed)
}

/// `cargo xtask golden --bless [NAME...]` for the workspace at `root`.
pub fn run_bless(root: &Path, names: &[String]) -> Result<Vec<Blessed>> {
    let cases = select(all_cases(root)?, names)?;
    bless(&cases, &root.join("golden"))
}
