//! `tracer check`: validate scene files without rendering.

use crate::args::CheckArgs;
use crate::console::{self, note};
use crate::error::{scene_outcome, Outcome};
use crate::report;
use tracer_pipeline::Checked;

pub fn run(args: &CheckArgs) -> Outcome {
    let color = report::color_wanted();
    let mut outcome = Outcome::Ok;
    let mut bad = 0;
    let mut no_camera = false;
    for scene in &args.scenes {
        match tracer_pipeline::load_or_part(scene) {
            Ok(Checked::Whole(loaded)) => {
                report::warnings(&loaded, &tracer_pipeline::Options::default());
                let gltf = scene_format::gltf::scene::is_gltf(scene);
                let summary = (gltf || args.json)
                    .then(|| tracer_pipeline::summary(&loaded))
                    .flatten();
                match summary.as_ref().filter(|_| gltf) {
                    Some(s) => note!("ok: {}: {}", scene.display(), s.line()),
                    None => note!("ok: {}", scene.display()),
                }
                if let Some(s) = summary.filter(|_| args.json) {
                    let mut line = serde_json::json!({ "file": scene });
                    let fields = serde_json::to_value(&s).unwrap_or_default();
                    if let (Some(o), Some(f)) = (line.as_object_mut(), fields.as_object()) {
                        o.extend(f.clone());
                    }
                    if console::stdout(&format!("{line}\n")).is_err() {
                        return Outcome::Failure;
                    }
                }
            }
            Ok(Checked::Part(loaded)) if args.part => {
                report::warnings(&loaded, &tracer_pipeline::Options::default());
                note!(
                    "ok: {}, as a file for a scene to include (it has no [camera], which \
                     rendering it on its own needs; the materials it names from other files \
                     are checked with the scene)",
                    scene.display()
                );
            }
            Ok(Checked::Part(loaded)) => {
                report::warnings(&loaded, &tracer_pipeline::Options::default());
                // A student who forgot the camera must not read "ok".
                note!(
                    "warning: {0} has no [camera], so it cannot be rendered: rendering needs a \
                     [camera] (eye, look_at). Its other keys are right as far as they go. If it \
                     is a file for scenes to include, `tracer check --part {0}` checks it as one",
                    scene.display()
                );
                no_camera = true;
            }
            Err(e) => {
                bad += 1;
                console::stderr_report(&report::render(&e, color));
                outcome = outcome.max(scene_outcome(&e));
            }
        }
    }
    // Exit 1: not a mistake in a file (2), but not a scene that renders.
    if no_camera && outcome == Outcome::Ok {
        outcome = Outcome::Failure;
    }
    if bad > 0 {
        note!(
            "{bad} of {} scene file{} failed the check",
            args.scenes.len(),
            if args.scenes.len() == 1 { "" } else { "s" }
        );
    }
    outcome
}
