//! `tracer schema`: the JSON Schema of scene files, for editors.

pub fn run() -> anyhow::Result<()> {
    crate::console::stdout(&format!("{}\n", scene_format::schema::json_schema()))
}
