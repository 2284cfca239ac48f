//! `tracer compare --report DIR`: a class's images against the scenes they
//! are named after, each scene rendered once; the report written whole.
//!
//! The naming rule: an image (.png, .jpg, .jpeg, in DIR or its folders) is
//! of the scene whose name is its file stem, or the part of its stem before
//! a `-` (the longest such name wins: `illumination-ambient-bob.png` is of
//! `illumination-ambient`, not `illumination`); failing that, the same of
//! its folder's name (`illumination/bob.png`). A scene's name is its path
//! below the scenes' folder without the extension, `-` for `/`, as the
//! goldens are named (`bench/bunny.toml` is `bench-bunny`).

use super::comparison::Comparison;
use super::input::{self, BadInput, Reference};
use super::page::{self, Class, Entry, Report, Unmatched, Unreadable};
use super::pair::percent;
use crate::console::{self, note};
use anyhow::Result;
use rayon::prelude::*;
use scene_format::visible::escape_controls;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use tracer_pipeline::Input;

/// The extensions of the images compared.
const IMAGE_EXTENSIONS: [&str; 3] = ["png", "jpg", "jpeg"];
/// The extensions of scene files.
const SCENE_EXTENSIONS: [&str; 2] = ["toml", "json"];

/// Compares and writes the report; true when every image is within tolerance.
pub fn run(
    dir: &Path,
    scenes: &Path,
    out: &Path,
    tolerance: u8,
    samples: Option<u32>,
) -> Result<bool> {
    page::check_out(out)?;
    let names = scene_names(scenes)?;
    let (matched, unmatched) = submissions(dir, out, &names)?;
    for u in &unmatched {
        note!("skipped: {} {}", u.path.display(), u.why());
    }
    if matched.is_empty() {
        return Err(BadInput(format!(
            "{}: no image is named after a scene of {} (e.g. illumination.png, \
             alice/illumination.png or illumination-alice.png)",
            dir.display(),
            scenes.display()
        ))
        .into());
    }
    let (references, failed) = render_scenes(&matched, &names, samples);
    // A scene that cannot be rendered leaves its images uncompared, not
    // the whole class.
    let (matched, uncompared): (Vec<_>, Vec<_>) = matched
        .into_iter()
        .partition(|(_, scene)| references.contains_key(scene));
    if matched.is_empty() {
        return Err(BadInput(
            "no image was compared: none of the scenes they are named after could be rendered (see above)".to_string(),
        )
        .into());
    }
    let mut unreadable = Vec::new();
    for (path, scene) in uncompared {
        let why = failed[&scene].clone();
        note!("not compared: {}: {why}", path.display());
        unreadable.push(Unreadable {
            path,
            scene,
            why,
            scene_failed: true,
        });
    }
    let report = Report::begin(out)?;
    for (scene, reference) in &references {
        report.reference(scene, reference)?;
    }
    let (mut entries, more) = compare_all(matched, &references, tolerance, &report)?;
    unreadable.extend(more);
    entries.sort_by(|a, b| Comparison::worse_first(&a.comparison, &b.comparison));
    let class = Class {
        entries,
        unreadable,
        unmatched,
    };
    report.finish(out, &class, &references, tolerance)?;
    console::stdout(&table(&class, references.len()))?;
    note!("report -> {}", out.join("index.html").display());
    Ok(class.unreadable.is_empty()
        && class
            .entries
            .iter()
            .all(|e| e.comparison.within_tolerance()))
}

/// Each image compared with its scene's reference, its copy and heat-map
/// written to the report at once: a few images at a time (one per
/// thread) are in memory, whatever the size of the class. Those that
/// cannot be read are reported beside the others' results: one
/// student's broken file is not the end of the report.
fn compare_all(
    matched: Vec<(PathBuf, String)>,
    references: &BTreeMap<String, Reference>,
    tolerance: u8,
    report: &Report,
) -> Result<(Vec<Entry>, Vec<Unreadable>)> {
    let mut entries = Vec::new();
    let mut unreadable = Vec::new();
    let at_once = rayon::current_num_threads().max(1);
    let indexed: Vec<_> = matched.into_iter().enumerate().collect();
    for group in indexed.chunks(at_once) {
        // Read in turn, so their notes come in path order.
        let mut read = Vec::new();
        for (index, (path, scene)) in group {
            match input::image_at(path) {
                Ok(image) => read.push((*index, path, scene, image)),
                Err(why) => {
                    note!("not compared: {}: {why}", path.display());
                    unreadable.push(Unreadable {
                        path: path.clone(),
                        scene: scene.clone(),
                        why,
                        scene_failed: false,
                    });
                }
            }
        }
        let compared: Vec<Result<Entry>> = read
            .into_par_iter()
            .map(|(index, path, scene, image)| {
                let mut comparison = Comparison::new(&image, &references[scene], tolerance);
                let heat_map = comparison.take_heat_map();
                report.image(index, &image, heat_map.as_ref())?;
                Ok(Entry {
                    path: path.clone(),
                    scene: scene.clone(),
                    index,
                    comparison,
                    heat_map: heat_map.is_some(),
                })
            })
            .collect();
        for entry in compared {
            entries.push(entry?);
        }
    }
    Ok((entries, unreadable))
}

/// Every scene file below `scenes` by its name.
fn scene_names(scenes: &Path) -> Result<BTreeMap<String, PathBuf>> {
    let mut names = BTreeMap::new();
    for path in files(scenes, &SCENE_EXTENSIONS)? {
        let name = relative_name(&path, scenes);
        if let Some(other) = names.insert(name.clone(), path.clone()) {
            return Err(BadInput(format!(
                "{} and {} are both named `{name}`: one image name cannot tell them apart",
                other.display(),
                path.display()
            ))
            .into());
        }
    }
    Ok(names)
}

/// `bench/bunny.toml` below `root`: `bench-bunny`.
fn relative_name(path: &Path, root: &Path) -> String {
    let relative = path.strip_prefix(root).unwrap_or(path).with_extension("");
    let parts: Vec<String> = relative
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    parts.join("-")
}

/// The images below `dir` (not in `out`) with their scene's name, and
/// those named after no scene, in path order.
#[allow(clippy::type_complexity)]
fn submissions(
    dir: &Path,
    out: &Path,
    names: &BTreeMap<String, PathBuf>,
) -> Result<(Vec<(PathBuf, String)>, Vec<Unmatched>)> {
    let out = out.canonicalize().ok();
    let mut matched = Vec::new();
    let mut unmatched = Vec::new();
    for path in files(dir, &IMAGE_EXTENSIONS)? {
        // A report written into DIR earlier is not a submission.
        if out
            .as_ref()
            .is_some_and(|o| path.canonicalize().is_ok_and(|p| p.starts_with(o)))
        {
            continue;
        }
        match scene_of(&path, names) {
            Some(scene) => matched.push((path, scene.to_string())),
            None => {
                let name_not_text = !name_is_text(&path);
                unmatched.push(Unmatched {
                    path,
                    name_not_text,
                })
            }
        }
    }
    Ok((matched, unmatched))
}

/// Whether the names the rule reads (the file's stem and its folder's
/// name) are text: a name that is not UTF-8 cannot match a scene's.
fn name_is_text(path: &Path) -> bool {
    let stem = path.file_stem().is_none_or(|s| s.to_str().is_some());
    let folder = path
        .parent()
        .and_then(Path::file_name)
        .is_none_or(|f| f.to_str().is_some());
    stem && folder
}

/// The scene `path` is named after (see the module's rule).
pub fn scene_of<'a>(path: &Path, names: &'a BTreeMap<String, PathBuf>) -> Option<&'a str> {
    let stem = path.file_stem()?.to_str()?;
    let folder = path.parent()?.file_name().and_then(|f| f.to_str());
    longest_name(stem, names).or_else(|| longest_name(folder?, names))
}

/// The longest scene name that is `word` or the part of it before a `-`.
fn longest_name<'a>(word: &str, names: &'a BTreeMap<String, PathBuf>) -> Option<&'a str> {
    let prefixes = word.match_indices('-').map(|(i, _)| &word[..i]);
    std::iter::once(word)
        .chain(prefixes)
        .filter_map(|candidate| names.get_key_value(candidate))
        .map(|(name, _)| name.as_str())
        .max_by_key(|name| name.len())
}

/// The files below `dir` with one of `extensions` (any case), in path
/// order; hidden files and folders and earlier reports are left out, and
/// so (said on stderr) is anything else than a file or a link to one.
fn files(dir: &Path, extensions: &[&str]) -> Result<Vec<PathBuf>> {
    if !dir.is_dir() {
        return Err(BadInput(format!("{}: not a folder", dir.display())).into());
    }
    // Hidden files, and reports written earlier (their images are copies
    // of submissions and references, not submissions).
    let hidden = |e: &walkdir::DirEntry| {
        e.depth() > 0
            && (e.file_name().to_string_lossy().starts_with('.')
                || e.file_type().is_dir() && page::is_report(e.path()))
    };
    let mut found = Vec::new();
    for entry in walkdir::WalkDir::new(dir)
        .sort_by_file_name()
        .into_iter()
        .filter_entry(|e| !hidden(e))
    {
        let entry = entry.map_err(|e| BadInput(format!("cannot read {}: {e}", dir.display())))?;
        let wanted = entry
            .path()
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| extensions.iter().any(|x| e.eq_ignore_ascii_case(x)));
        if !wanted || entry.file_type().is_dir() {
            continue;
        }
        // A link is followed to a file; a pipe or device would never end.
        if std::fs::metadata(entry.path()).is_ok_and(|m| m.is_file()) {
            found.push(entry.into_path());
        } else {
            note!("skipped: {} is not a file", entry.path().display());
        }
    }
    Ok(found)
}

/// Each scene the images name, rendered once; those that could not be
/// (why shown on stderr, a scene's mistakes as `tracer check` shows them)
/// by why: one scene's trouble (mistakes, `--samples` it cannot take) is
/// its images', not the class's.
fn render_scenes(
    matched: &[(PathBuf, String)],
    names: &BTreeMap<String, PathBuf>,
    samples: Option<u32>,
) -> (BTreeMap<String, Reference>, BTreeMap<String, String>) {
    let mut references = BTreeMap::new();
    let mut failed = BTreeMap::new();
    for (_, scene) in matched {
        if references.contains_key(scene) || failed.contains_key(scene) {
            continue;
        }
        let path = &names[scene];
        note!("rendering {}", path.display());
        let shown = path.display();
        let why = match tracer_pipeline::load(&Input::File(path.clone())) {
            Ok(loaded) => match input::render(loaded, None, samples) {
                Ok(reference) => {
                    references.insert(scene.clone(), reference);
                    continue;
                }
                Err(e) => format!("its scene {shown} could not be rendered: {e:#}"),
            },
            Err(e) if tracer_pipeline::scene_error_is_bad_input(&e) => {
                crate::error::finish(Err(e.into()));
                format!("its scene {shown} has mistakes (tracer check {shown} shows them)")
            }
            Err(e) => format!("its scene {shown} could not be read: {e}"),
        };
        note!("error: {why}");
        failed.insert(scene.clone(), why);
    }
    (references, failed)
}

/// The summary on stdout: one line per image, worst first, then the
/// images that could not be read.
fn table(class: &Class, scenes: usize) -> String {
    let entries = &class.entries;
    // Names from the class's files: their control characters made visible.
    let shown = |path: &Path| escape_controls(&path.display().to_string());
    let paths = entries
        .iter()
        .map(|e| shown(&e.path))
        .chain(class.unreadable.iter().map(|u| shown(&u.path)));
    let width = paths.map(|p| p.chars().count()).fold(5, usize::max);
    let scene_width = entries
        .iter()
        .map(|e| &e.scene)
        .chain(class.unreadable.iter().map(|u| &u.scene))
        .map(|s| escape_controls(s).chars().count())
        .fold(5, usize::max);
    let mut out = format!(
        "{:>12}  {:>6}  {:<width$}  {:<scene_width$}  mistakes\n",
        "off", "FLIP", "image", "scene"
    );
    let mut line = |off: &str, flip: &str, path: &Path, scene: &str, words: &str| {
        let line = format!(
            "{off:>12}  {flip:>6}  {:<width$}  {:<scene_width$}  {}",
            shown(path),
            escape_controls(scene),
            escape_controls(words)
        );
        out += line.trim_end();
        out.push('\n');
    };
    for e in entries {
        let flip = e
            .comparison
            .flip_mean()
            .map_or("-".to_string(), |f| format!("{f:.4}"));
        let words = e.comparison.words().join(", ");
        line(
            &percent(e.comparison.share()),
            &flip,
            &e.path,
            &e.scene,
            &words,
        );
    }
    for u in &class.unreadable {
        line("not compared", "-", &u.path, &u.scene, &u.why);
    }
    let within = entries
        .iter()
        .filter(|e| e.comparison.within_tolerance())
        .count();
    let _ = write!(
        out,
        "{} image{} against {scenes} scene{}: {within} within tolerance, {} not",
        entries.len(),
        if entries.len() == 1 { "" } else { "s" },
        if scenes == 1 { "" } else { "s" },
        entries.len() - within
    );
    if !class.unreadable.is_empty() {
        let _ = write!(out, "; {} not compared", class.unreadable.len());
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> BTreeMap<String, PathBuf> {
        list.iter()
            .map(|n| (n.to_string(), PathBuf::from(format!("{n}.toml"))))
            .collect()
    }

    #[test]
    fn an_image_is_of_the_longest_scene_name_it_starts_with() {
        let names = names(&["illumination", "illumination-ambient", "bench-bunny"]);
        let scene = |p: &str| scene_of(Path::new(p), &names);
        assert_eq!(scene("class/illumination.png"), Some("illumination"));
        assert_eq!(scene("alice/illumination.png"), Some("illumination"));
        assert_eq!(scene("illumination-alice.png"), Some("illumination"));
        assert_eq!(
            scene("illumination-ambient-bob.png"),
            Some("illumination-ambient")
        );
        assert_eq!(scene("bench-bunny-carol.jpg"), Some("bench-bunny"));
        assert_eq!(scene("illumination/dave.png"), Some("illumination"));
        // A name must end where a `-` or the stem does.
        assert_eq!(scene("illuminationx.png"), None);
        assert_eq!(scene("x/alice.png"), None);
    }

    #[test]
    fn a_scene_in_a_folder_is_named_as_its_golden() {
        let root = Path::new("scenes");
        assert_eq!(
            relative_name(Path::new("scenes/bench/bunny.toml"), root),
            "bench-bunny"
        );
        assert_eq!(
            relative_name(Path::new("scenes/texture.json"), root),
            "texture"
        );
    }
}
