//! `tracer convert`: a scene file from TOML to JSON or back, every value and
//! the structure kept (comments are not).

use anyhow::{bail, Context};
use scene_format::Format;
use std::path::{Path, PathBuf};
use tracer_cli::tool_args::ConvertArgs;
use tracer_pipeline::output::{self, PendingFile};

pub fn run(args: &ConvertArgs) -> anyhow::Result<()> {
    // An archive loads as a scene, but its bytes are not a scene's text.
    if args
        .scene
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("zip"))
    {
        let error = tracer_pipeline::pack::PackError::NotConverted(args.scene.clone());
        return Err(tracer_pipeline::Error::from(error).into());
    }
    if scene_format::gltf::scene::is_gltf(&args.scene) {
        return convert_gltf(args);
    }
    let to = match &args.output {
        Some(path) => format_of(path)?,
        None => other(format_of(&args.scene)?),
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&args.scene, to));
    // A scene with mistakes is reported as `tracer check` does, not converted.
    let files_read = match scene_format::load_file_or_part(&args.scene) {
        Ok(scene_format::Checked::Whole(loaded) | scene_format::Checked::Part(loaded)) => {
            loaded.files_read
        }
        Err(e) => return Err(tracer_pipeline::Error::from(e).into()),
    };
    output::check_not_an_input(&output, &files_read).map_err(tracer_pipeline::Error::from)?;
    let text = std::fs::read_to_string(&args.scene)
        .with_context(|| format!("cannot read {}", args.scene.display()))?;
    let converted = convert(&text, format_of(&args.scene)?, to)?;
    let pending = PendingFile::create(&output).map_err(tracer_pipeline::Error::from)?;
    pending
        .write_bytes(converted.as_bytes())
        .map_err(tracer_pipeline::Error::from)?;
    Ok(())
}

/// A glTF file as a scene file that holds it as a `gltf` object and spells
/// out the camera, lights and environment `tracer render` gives it, for a
/// user to edit (default: `NAME.toml` in the current folder).
fn convert_gltf(args: &ConvertArgs) -> anyhow::Result<()> {
    let to = match &args.output {
        Some(path) => format_of(path)?,
        None => Format::Toml,
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&args.scene, to));
    let loaded = match scene_format::load_file_or_part(&args.scene) {
        Ok(scene_format::Checked::Whole(loaded) | scene_format::Checked::Part(loaded)) => loaded,
        Err(e) => return Err(tracer_pipeline::Error::from(e).into()),
    };
    output::check_not_an_input(&output, &loaded.files_read)
        .map_err(tracer_pipeline::Error::from)?;
    let scene_format::SceneKind::Scene3d(mut file) = loaded.kind else {
        bail!("expected a 3D scene of {}", args.scene.display());
    };
    let folder = output.parent().unwrap_or(Path::new(""));
    let model = relative_to(folder, &args.scene);
    for object in &mut file.objects {
        if let Some(g) = object.gltf.as_mut() {
            g.file = model.clone();
        }
    }
    let mut value = serde_json::to_value(&file)?;
    as_written(&mut value);
    let text = match to {
        Format::Json => {
            let mut out = String::new();
            write_json(&value, 0, &mut out);
            out + "\n"
        }
        Format::Toml => to_toml(value)?,
    };
    let pending = PendingFile::create(&output).map_err(tracer_pipeline::Error::from)?;
    pending
        .write_bytes(text.as_bytes())
        .map_err(tracer_pipeline::Error::from)?;
    Ok(())
}

/// Every number of a tree made from the scene's f32 values written as its
/// shortest decimal (2.2, not the f64 2.200000047683716).
fn as_written(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Number(n) if n.is_f64() => {
            let x = tracer_pipeline::as_written(n.as_f64().unwrap_or(0.0) as f32);
            if let Some(tidy) = serde_json::Number::from_f64(x) {
                *n = tidy;
            }
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(as_written),
        serde_json::Value::Object(members) => members.values_mut().for_each(as_written),
        _ => {}
    }
}

/// `path` as a path relative to the folder `from` (both taken from the
/// current folder), with `/` between its parts: what a scene in `from`
/// names it by.
fn relative_to(from: &Path, path: &Path) -> String {
    let absolute = |p: &Path| {
        let p = if p.as_os_str().is_empty() {
            Path::new(".")
        } else {
            p
        };
        std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf())
    };
    let (from, path) = (absolute(from), absolute(path));
    let (a, b): (Vec<_>, Vec<_>) = (from.components().collect(), path.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let parts: Vec<String> = std::iter::repeat_n("..".to_string(), a.len() - common)
        .chain(
            b[common..]
                .iter()
                .map(|c| c.as_os_str().to_string_lossy().into_owned()),
        )
        .collect();
    parts.join("/")
}

fn format_of(path: &Path) -> anyhow::Result<Format> {
    Format::from_path(path).ok_or_else(|| {
        tracer_pipeline::Error::from(scene_format::SceneError::UnknownFormat {
            file: path.to_path_buf(),
        })
        .into()
    })
}

fn other(format: Format) -> Format {
    match format {
        Format::Toml => Format::Json,
        Format::Json => Format::Toml,
    }
}

/// The scene's file name with the extension of `format`, in the current folder.
fn default_output(scene: &Path, format: Format) -> PathBuf {
    let stem = scene.file_stem().unwrap_or_default();
    PathBuf::from(stem).with_extension(match format {
        Format::Toml => "toml",
        Format::Json => "json",
    })
}

/// The TOML key and JSON member an editor reads the schema from.
const SCHEMA_KEY: &str = "$schema";
const SCHEMA_DIRECTIVE: &str = "#:schema ";

/// Scene text in another format (or the same one, rewritten). Parsed into
/// a tree of plain values, not into the scene model: defaults are not
/// filled in, `include` stays a list of file names. A TOML `#:schema`
/// directive becomes the JSON `$schema` member (3D and canvas scenes alike).
pub fn convert(text: &str, from: Format, to: Format) -> anyhow::Result<String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut value: serde_json::Value = match from {
        Format::Toml => toml::from_str(text)?,
        Format::Json => serde_json::from_str(text)?,
    };
    let Some(table) = value.as_object_mut() else {
        bail!("expected a table at the top of the scene file");
    };
    if from == Format::Toml && !table.contains_key(SCHEMA_KEY) {
        if let Some(schema) = toml_schema_directive(text) {
            table.insert(SCHEMA_KEY.into(), schema.into());
        }
    }
    match to {
        Format::Json => {
            let mut out = String::new();
            write_json(&value, 0, &mut out);
            Ok(out + "\n")
        }
        Format::Toml => to_toml(value),
    }
}

/// The path of a `#:schema PATH` directive on the first line (taplo's).
fn toml_schema_directive(text: &str) -> Option<&str> {
    let first = text.lines().next()?;
    let path = first.strip_prefix(SCHEMA_DIRECTIVE)?.trim();
    (!path.is_empty()).then_some(path)
}

/// TOML text of a JSON tree: its `$schema` as a `#:schema` directive, and
/// members that are `null` left out (TOML has no null; for a scene file a
/// null member means the same as a missing one).
fn to_toml(mut value: serde_json::Value) -> anyhow::Result<String> {
    drop_nulls(&mut value);
    let table = value.as_object_mut().expect("checked by the caller");
    let directive = match table.get(SCHEMA_KEY) {
        Some(serde_json::Value::String(path)) => {
            // On the directive's one line, a line break would start TOML
            // of its own: keys the JSON file never had.
            if path.chars().any(char::is_control) {
                bail!("`{SCHEMA_KEY}` holds a line break or another control character; expected the path of a schema file");
            }
            let line = format!("{SCHEMA_DIRECTIVE}{path}\n");
            table.remove(SCHEMA_KEY);
            line
        }
        _ => String::new(),
    };
    Ok(directive + &toml::to_string(&value)?)
}

fn drop_nulls(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Object(map) => {
            map.retain(|_, v| !v.is_null());
            map.values_mut().for_each(drop_nulls);
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(drop_nulls),
        _ => {}
    }
}

/// The widest array written on one line, in characters.
const INLINE_ARRAY: usize = 72;

/// Pretty JSON as a person writes a scene: a vector, a colour or a
/// triangle on one line (`[0, 1.5, 8]`), tables indented.
fn write_json(value: &serde_json::Value, indent: usize, out: &mut String) {
    use serde_json::Value;
    let pad = |n: usize| "  ".repeat(n);
    match value {
        Value::Object(map) if !map.is_empty() => {
            out.push_str("{\n");
            for (i, (key, item)) in map.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                out.push_str(&Value::from(key.as_str()).to_string());
                out.push_str(": ");
                write_json(item, indent + 1, out);
                out.push_str(if i + 1 < map.len() { ",\n" } else { "\n" });
            }
            out.push_str(&pad(indent));
            out.push('}');
        }
        Value::Array(items) if !fits_on_a_line(value) => {
            out.push_str("[\n");
            for (i, item) in items.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                write_json(item, indent + 1, out);
                out.push_str(if i + 1 < items.len() { ",\n" } else { "\n" });
            }
            out.push_str(&pad(indent));
            out.push(']');
        }
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(one_line).collect();
            out.push_str(&format!("[{}]", items.join(", ")));
        }
        other => out.push_str(&other.to_string()),
    }
}

/// An array of numbers, strings or such arrays, short enough for one line.
fn fits_on_a_line(value: &serde_json::Value) -> bool {
    fn no_tables(v: &serde_json::Value) -> bool {
        match v {
            serde_json::Value::Object(_) => false,
            serde_json::Value::Array(items) => items.iter().all(no_tables),
            _ => true,
        }
    }
    no_tables(value) && one_line(value).len() <= INLINE_ARRAY
}

fn one_line(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::Array(items) => {
            let items: Vec<String> = items.iter().map(one_line).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_schema_with_a_line_break_cannot_write_toml_of_its_own() {
        let json = r#"{"$schema": "x\n[render]\nsamples = 4096\n#", "camera": {"eye": [0, 0, 1]}}"#;
        let error = convert(json, Format::Json, Format::Toml)
            .unwrap_err()
            .to_string();
        assert!(error.contains("holds a line break"), "{error}");
        let fine = convert(r#"{"$schema": "../s.json"}"#, Format::Json, Format::Toml).unwrap();
        assert_eq!(fine, "#:schema ../s.json\n");
    }
}
