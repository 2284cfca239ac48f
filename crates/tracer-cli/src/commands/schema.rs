//! `tracer schema`: the JSON Schema of scene files, for editors.

pub fn run() -> anyhow::Result<()> {
    println!("{}", scene_format::schema::json_schema());
    Ok(())
}
