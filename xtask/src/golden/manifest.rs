//! `golden/golden.toml`: the tolerances, the default and per image.
//!
//! ```toml
//! [default]                     # optional; these are the built-in values
//! channel_tolerance = 2         # a pixel differs when a channel differs by more (of 255)
//! max_differing_percent = 0.1   # an image passes when at most this % of pixels differ
//!
//! [scenes.texture]              # one image's own tolerance; keys left out
//! channel_tolerance = 4         # come from [default]
//! ```

use super::compare::Tolerance;
use anyhow::{bail, Context, Result};
use scene_format::Location;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;
use toml::Spanned;

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Manifest {
    pub default: Tolerance,
    pub scenes: BTreeMap<String, Tolerance>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ManifestFile {
    #[serde(default)]
    default: ToleranceFile,
    #[serde(default)]
    scenes: BTreeMap<String, ToleranceFile>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct ToleranceFile {
    channel_tolerance: Option<u8>,
    max_differing_percent: Option<Spanned<f64>>,
}

impl Manifest {
    /// Reads the manifest; a missing file means the built-in defaults.
    pub fn load(path: &Path) -> Result<Manifest> {
        match std::fs::read_to_string(path) {
            Ok(text) => Manifest::parse(&text, path),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Manifest::default()),
            Err(e) => Err(e).with_context(|| format!("{}: cannot read", path.display())),
        }
    }

    /// Parses manifest text; `file` names it in errors.
    pub fn parse(text: &str, file: &Path) -> Result<Manifest> {
        let at = |offset: usize| {
            let l = Location::from_offset(text, offset);
            format!("{}:{}:{}", file.display(), l.line, l.column)
        };
        let raw: ManifestFile = toml::from_str(text).map_err(|e| {
            let place = e
                .span()
                .map_or_else(|| file.display().to_string(), |s| at(s.start));
            anyhow::anyhow!("{place}: {}", e.message().trim_end())
        })?;
        let default = apply(Tolerance::default(), &raw.default, "default", &at)?;
        let mut scenes = BTreeMap::new();
        for (name, t) in &raw.scenes {
            let key = format!("scenes.{name}");
            scenes.insert(name.clone(), apply(default, t, &key, &at)?);
        }
        Ok(Manifest { default, scenes })
    }

    pub fn tolerance(&self, name: &str) -> Tolerance {
        self.scenes.get(name).copied().unwrap_or(self.default)
    }

    /// A tolerance for a name that is no image is a typo: say so.
    pub fn check_names(&self, file: &Path, known: impl Fn(&str) -> bool) -> Result<()> {
        let unknown: Vec<&String> = self.scenes.keys().filter(|n| !known(n)).collect();
        if !unknown.is_empty() {
            bail!(
                "{}: [scenes.{}]: no image of that name (names are the golden PNGs' file stems)",
                file.display(),
                unknown
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join("], [scenes.")
            );
        }
        Ok(())
    }
}

fn apply(
    base: Tolerance,
    t: &ToleranceFile,
    key: &str,
    at: &dyn Fn(usize) -> String,
) -> Result<Tolerance> {
    let mut out = base;
    if let Some(c) = t.channel_tolerance {
        out.channel = c;
    }
    if let Some(p) = &t.max_differing_percent {
        let value = *p.get_ref();
        if !(0.0..=100.0).contains(&value) {
            bail!(
                "{}: {key}.max_differing_percent: expected a percentage from 0 to 100, found {value}",
                at(p.span().start)
            );
        }
        out.max_differing_percent = value;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Manifest> {
        Manifest::parse(text, Path::new("golden/golden.toml"))
    }

    #[test]
    fn empty_manifest_gives_the_defaults() {
        let m = parse("").unwrap();
        assert_eq!(m.tolerance("anything"), Tolerance::default());
        assert_eq!(m.default.channel, 2);
        assert_eq!(m.default.max_differing_percent, 0.1);
    }

    #[test]
    fn a_scene_override_inherits_what_it_leaves_out() {
        let m = parse(
            "[default]\nmax_differing_percent = 0.5\n\n[scenes.texture]\nchannel_tolerance = 4\n",
        )
        .unwrap();
        assert_eq!(
            m.tolerance("texture"),
            Tolerance {
                channel: 4,
                max_differing_percent: 0.5
            }
        );
        assert_eq!(
            m.tolerance("shadows"),
            Tolerance {
                channel: 2,
                max_differing_percent: 0.5
            }
        );
    }

    #[test]
    fn unknown_key_names_file_line_and_key() {
        let err = parse("[scenes.texture]\nchannel = 4\n")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("golden/golden.toml:2:1: "), "{err}");
        assert!(err.contains("unknown field `channel`"), "{err}");
    }

    #[test]
    fn out_of_range_values_are_errors_with_their_place() {
        let err = parse("[default]\nchannel_tolerance = 300\n")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("golden/golden.toml:2:"), "{err}");

        let err = parse("[scenes.a]\nmax_differing_percent = 150\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "golden/golden.toml:2:25: scenes.a.max_differing_percent: \
             expected a percentage from 0 to 100, found 150"
        );
    }

    #[test]
    fn a_tolerance_for_an_unknown_image_is_an_error() {
        let m = parse("[scenes.textrue]\nchannel_tolerance = 4\n").unwrap();
        let err = m
            .check_names(Path::new("golden.toml"), |n| n == "texture")
            .unwrap_err()
            .to_string();
        assert!(err.contains("[scenes.textrue]"), "{err}");
        assert!(m
            .check_names(Path::new("golden.toml"), |n| n == "textrue")
            .is_ok());
    }
}
