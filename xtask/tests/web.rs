//! The playground in headless Chromium: `cargo xtask web` builds the page
//! (crates/web for wasm32, the bundled scripts, the scenes), a static server
//! serves it, and each test scripts the live page over DevTools.

use headless::Browser;
use serde_json::Value;
use std::io::Write;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Duration;

const RENDER: Duration = Duration::from_secs(120);

/// The page, built once for all the tests, and its server's address.
fn page() -> SocketAddr {
    static PAGE: OnceLock<SocketAddr> = OnceLock::new();
    *PAGE.get_or_init(|| {
        let out = xtask::target_dir().join("web-test");
        xtask::web::build(&xtask::workspace_root(), &out).expect("cargo xtask web");
        xtask::web::serve::start(&out, "127.0.0.1:0").expect("serve")
    })
}

/// Chromium, or `None` with a notice when it or the wasm toolchain is
/// missing; under CI (`.ci/run` installs both) that fails instead.
fn chromium() -> Option<PathBuf> {
    let found = headless::find_chromium();
    let toolchain = xtask::web::toolchain::find();
    let missing = match (&found, &toolchain) {
        (None, _) => "Chromium (Debian: apt-get install chromium)".to_string(),
        (_, Err(e)) => format!("{e:#}"),
        _ => return found,
    };
    assert!(
        std::env::var_os("CI").is_none(),
        "CI is set but the playground's tests cannot run: {missing}"
    );
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED: the playground's tests need {missing}"
    );
    None
}

/// The image canvas's pixels, as the page encodes them in a PNG, decoded.
fn canvas_image(page: &mut Browser) -> anyhow::Result<image::RgbaImage> {
    use anyhow::Context;
    let url = page.eval("document.getElementById('image').toDataURL('image/png')")?;
    let url = url.as_str().context("no data URL")?;
    let b64 = url
        .strip_prefix("data:image/png;base64,")
        .context("not a PNG data URL")?;
    let bytes = headless::base64_decode(b64)?;
    Ok(image::load_from_memory(&bytes)?.to_rgba8())
}

/// The page at `query_and_fragment` (e.g. `?workers=2`), its first render done.
fn open(query_and_fragment: &str) -> Option<Browser> {
    let chromium = chromium()?;
    let url = format!("http://{}/{query_and_fragment}", page());
    let mut browser = Browser::open(&chromium, &url).unwrap();
    wait_done(&mut browser);
    Some(browser)
}

fn wait_done(browser: &mut Browser) {
    browser
        .wait_for(
            "document.getElementById('image').dataset.state === 'done'",
            RENDER,
        )
        .unwrap();
}

/// Picks `scene` (a path under scenes/) in the menu, as a user does.
fn choose_scene(browser: &mut Browser, scene: &str) {
    let path = serde_json::to_string(scene).unwrap();
    eval(
        browser,
        &format!(
            "(() => {{ const m = document.getElementById('scene-menu'); \
             m.value = {path}; m.dispatchEvent(new Event('change')); }})()"
        ),
    );
}

/// Picks `scene` and waits until its render is done.
fn render_scene(browser: &mut Browser, scene: &str) {
    choose_scene(browser, scene);
    browser
        .wait_for(
            &format!(
                "document.getElementById('image').dataset.state === 'done' && \
                 tracerPage.lastRender.scene === '{scene}'"
            ),
            RENDER,
        )
        .unwrap();
}

fn eval(browser: &mut Browser, expression: &str) -> Value {
    browser.eval(expression).unwrap()
}

/// Replaces the editor's text, as typing would.
fn type_text(browser: &mut Browser, text: &str) {
    let text = serde_json::to_string(text).unwrap();
    eval(
        browser,
        &format!(
            "(() => {{ const v = tracerPage.view; \
             v.dispatch({{changes: {{from: 0, to: v.state.doc.length, insert: {text}}}}}); }})()"
        ),
    );
}

/// The editor's text.
fn editor_text(browser: &mut Browser) -> String {
    let text = eval(browser, "tracerPage.view.state.doc.toString()");
    text.as_str().unwrap().to_string()
}

/// The text of the page's element of id `id`.
fn text_of(browser: &mut Browser, id: &str) -> String {
    let expression = format!("document.getElementById('{id}').textContent");
    eval(browser, &expression).as_str().unwrap().to_string()
}

fn status(browser: &mut Browser) -> String {
    text_of(browser, "status")
}

/// The canvas equals `golden/NAME.png` bit for bit.
fn assert_golden(browser: &mut Browser, name: &str) {
    let shown = canvas_image(browser).unwrap();
    let golden = image::open(xtask::workspace_root().join(format!("golden/{name}.png")))
        .unwrap()
        .to_rgb8();
    assert_eq!(shown.dimensions(), golden.dimensions(), "{name}");
    let differing = shown
        .pixels()
        .zip(golden.pixels())
        .filter(|(s, g)| s.0[..3] != g.0[..3] || s.0[3] != 255)
        .count();
    assert_eq!(differing, 0, "{name}: pixels differing from the golden");
}

#[test]
fn the_default_scene_renders_as_its_golden_and_the_menu_lists_every_scene() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    assert_golden(&mut page, "reflectance2");
    assert!(
        status(&mut page).contains("Mrays/s"),
        "{}",
        status(&mut page)
    );
    let options = eval(
        &mut page,
        "[...document.getElementById('scene-menu').options].map(o => o.value)",
    );
    let options: Vec<&str> = options
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    // The lab's tables first, in the lab's order; then every other scene.
    assert_eq!(options[..12], xtask::web::LAB_SCENES);
    let scenes = xtask::golden::scene_files(&xtask::workspace_root().join("scenes")).unwrap();
    assert_eq!(options.len(), scenes.len() + 1, "{options:?}");
    assert!(options.contains(&"bench/bunny.toml"), "{options:?}");
    assert_eq!(
        eval(&mut page, "document.getElementById('scene-menu').value"),
        "reflectance2.toml"
    );
}

#[test]
fn a_scene_with_files_from_the_menu_renders_as_its_golden_on_three_workers() {
    // Three bands of uneven height: the merge must still be the one image.
    let Some(mut page) = open("?workers=3") else {
        return;
    };
    choose_scene(&mut page, "textures.toml");
    page.wait_for(
        "document.getElementById('status').textContent.startsWith('textures.toml: 480x320')",
        RENDER,
    )
    .unwrap();
    wait_done(&mut page);
    assert_golden(&mut page, "textures");
    // Its archive (Download .zip) renders with `tracer render` as the page shows it.
    let zip = eval(&mut page, "tracerPage.sceneZipBase64()");
    let zip = headless::base64_decode(zip.as_str().unwrap()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("textures.zip");
    std::fs::write(&path, zip).unwrap();
    let loaded = tracer_pipeline::load(&tracer_pipeline::Input::File(path)).unwrap();
    let rendered = tracer_pipeline::render(&loaded, &Default::default(), &|_| {}).unwrap();
    let shown = canvas_image(&mut page).unwrap();
    let rgb = rendered.image.to_rgb8();
    assert!(
        rgb.pixels()
            .zip(shown.pixels())
            .all(|(a, b)| a.0 == b.0[..3]),
        "the archive renders otherwise"
    );
    // Dropped back into the page, the archive renders as it is.
    eval(
        &mut page,
        "(() => { const b64 = tracerPage.sceneZipBase64(); \
         tracerPage.addFiles({'t.zip': Uint8Array.from(atob(b64), c => c.charCodeAt(0))}); })()",
    );
    page.wait_for(
        "document.getElementById('status').textContent.startsWith('t.zip: 480x320')",
        RENDER,
    )
    .unwrap();
    wait_done(&mut page);
    assert_golden(&mut page, "textures");
}

#[test]
fn an_error_shows_at_its_line_and_goes_when_fixed() {
    let Some(mut page) = open("?workers=1") else {
        return;
    };
    let good = editor_text(&mut page);
    let bad = good.replacen("fov = 50", "fvo = 50", 1);
    assert_ne!(bad, good);
    let line = bad.lines().position(|l| l.starts_with("fvo")).unwrap() + 1;
    type_text(&mut page, &bad);
    page.wait_for(
        "document.getElementById('image').dataset.state === 'error'",
        RENDER,
    )
    .unwrap();
    let text = status(&mut page);
    // Worded as `tracer check` words it, at its line and column.
    assert!(
        text.contains(&format!("reflectance2.toml:{line}:1")),
        "{text}"
    );
    assert!(text.contains("unknown key `fvo`"), "{text}");
    assert!(text.contains("did you mean `fov`?"), "{text}");
    // The editor marks that line.
    let marked = eval(
        &mut page,
        "[...document.querySelectorAll('.cm-line')].findIndex(l => l.querySelector('.cm-lintRange-error')) + 1",
    );
    assert_eq!(marked, Value::from(line));
    type_text(&mut page, &good);
    wait_done(&mut page);
    let marks = eval(
        &mut page,
        "document.querySelectorAll('.cm-lintRange-error').length",
    );
    assert_eq!(marks, Value::from(0));
    assert_golden(&mut page, "reflectance2");
}

#[test]
fn a_share_link_opens_with_its_scene() {
    let Some(mut page) = open("?workers=1") else {
        return;
    };
    let text = eval(&mut page, "tracerPage.view.state.doc.toString()");
    let edited = text
        .as_str()
        .unwrap()
        .replacen("width = 500", "width = 250", 1)
        .replacen("height = 400", "height = 200", 1)
        + "# shared ünïcode\n";
    type_text(&mut page, &edited);
    wait_done(&mut page);
    eval(&mut page, "document.getElementById('share').click()");
    page.wait_for(
        "!!document.getElementById('share').dataset.link",
        Duration::from_secs(10),
    )
    .unwrap();
    let link = eval(&mut page, "document.getElementById('share').dataset.link");
    let link = link.as_str().unwrap().to_string();
    assert!(link.contains("#scene=reflectance2.toml&text="), "{link}");
    drop(page);
    let mut opened = Browser::open(&chromium().unwrap(), &link).unwrap();
    wait_done(&mut opened);
    let shown = eval(&mut opened, "tracerPage.view.state.doc.toString()");
    assert_eq!(shown.as_str().unwrap(), edited);
    assert_eq!(
        eval(
            &mut opened,
            "[tracerPage.lastRender.width, tracerPage.lastRender.height]"
        ),
        serde_json::json!([250, 200])
    );
    // The link pasted into a tab already open on another scene opens too.
    render_scene(&mut opened, "shadows.toml");
    let fragment = &link[link.find('#').unwrap()..];
    eval(
        &mut opened,
        &format!(
            "location.hash = {}",
            serde_json::to_string(fragment).unwrap()
        ),
    );
    opened
        .wait_for(
            "document.getElementById('image').dataset.state === 'done' && \
             tracerPage.lastRender.scene === 'reflectance2.toml'",
            RENDER,
        )
        .unwrap();
    let shown = eval(&mut opened, "tracerPage.view.state.doc.toString()");
    assert_eq!(shown.as_str().unwrap(), edited);
    // A link cut short says so.
    eval(&mut opened, "location.hash = '#scene=x.toml&text=AAAA!!!'");
    opened
        .wait_for(
            "document.getElementById('notice').textContent.includes('could not be read')",
            Duration::from_secs(10),
        )
        .unwrap();
    // A link whose text inflates past the page's limit of a scene file is
    // refused, and the page says why (the link made here, in the tab).
    eval(
        &mut opened,
        "(async () => { \
           const spaces = new Uint8Array(64 * 1024 * 1024 + 1).fill(32); \
           const packed = new Blob([spaces]).stream().pipeThrough(new CompressionStream('deflate-raw')); \
           const bytes = new Uint8Array(await new Response(packed).arrayBuffer()); \
           let s = ''; for (const b of bytes) s += String.fromCharCode(b); \
           location.hash = '#scene=x.toml&text=' + btoa(s).replace(/\\+/g, '-').replace(/\\//g, '_').replace(/=+$/, ''); \
         })()",
    );
    opened
        .wait_for(
            "document.getElementById('notice').textContent.includes('was not opened: its scene is over 64 MiB once inflated')",
            Duration::from_secs(30),
        )
        .unwrap();
    assert_eq!(
        eval(&mut opened, "tracerPage.view.state.doc.toString()")
            .as_str()
            .unwrap(),
        edited
    );
}

#[test]
fn a_dropped_obj_renders() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    // A square of two triangles filling the view's centre, lit from the eye.
    let obj = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";
    let scene = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 64\nheight = 48\n\
                 [[lights]]\nposition = [0, 0, 5]\n\
                 [[objects]]\nmesh = { obj = \"square.obj\" }\n\
                 material = { diffuse = [0.8, 0, 0] }\n";
    let files = serde_json::json!({ "square.obj": obj, "dropped.toml": scene });
    eval(&mut page, &format!("tracerPage.addFiles({files})"));
    page.wait_for(
        "document.getElementById('status').textContent.startsWith('dropped.toml: 64x48')",
        RENDER,
    )
    .unwrap();
    wait_done(&mut page);
    let shown = canvas_image(&mut page).unwrap();
    assert_eq!(shown.dimensions(), (64, 48));
    let centre = shown.get_pixel(32, 24).0;
    assert!(centre[0] > 150 && centre[1] == 0, "{centre:?}");
    assert_eq!(shown.get_pixel(0, 0).0, [0, 0, 0, 255]);
    // The file the scene reads is named: without it, the error says so.
    eval(
        &mut page,
        "tracerPage.addFiles({'dropped.toml': \
         tracerPage.view.state.doc.toString().replace('square.obj', 'missing.obj')})",
    );
    page.wait_for(
        "document.getElementById('image').dataset.state === 'error'",
        RENDER,
    )
    .unwrap();
    let text = status(&mut page);
    assert!(text.contains("missing.obj"), "{text}");
}

#[test]
fn a_panic_in_the_wasm_shows_as_an_error_and_the_next_edit_renders() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    let text = editor_text(&mut page);
    eval(&mut page, "tracerPage.panicNext = true");
    type_text(&mut page, &format!("{text}# edited\n"));
    page.wait_for(
        "document.getElementById('image').dataset.state === 'error'",
        RENDER,
    )
    .unwrap();
    let shown = status(&mut page);
    assert!(
        shown.contains("the tracer panicked") && shown.contains("asked for by tracer_panic"),
        "{shown}"
    );
    type_text(&mut page, &text);
    wait_done(&mut page);
    assert_golden(&mut page, "reflectance2");
}

#[test]
fn every_scene_of_the_menu_renders_as_its_golden_within_maths_last_bits() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    let scenes = xtask::web::scene_entries(&xtask::workspace_root().join("scenes")).unwrap();
    let mut differing = Vec::new();
    for (rep, scene) in scenes.iter().enumerate() {
        let path = serde_json::to_string(&scene.path).unwrap();
        choose_scene(&mut page, &scene.path);
        page.wait_for(
            &format!(
                "document.getElementById('image').dataset.state === 'done' && \
                 tracerPage.lastRender.scene === {path} && tracerPage.renders > {}",
                rep + 1
            ),
            RENDER,
        )
        .unwrap();
        let name = scene.path.trim_end_matches(".toml").replace('/', "-");
        let shown = canvas_image(&mut page).unwrap();
        let golden = image::open(xtask::workspace_root().join(format!("golden/{name}.png")))
            .unwrap()
            .to_rgb8();
        assert_eq!(shown.dimensions(), golden.dimensions(), "{name}");
        let mut count = 0;
        let mut most = 0;
        for (s, g) in shown.pixels().zip(golden.pixels()) {
            if s.0[..3] != g.0[..3] {
                count += 1;
                let step = (0..3).map(|c| s[c].abs_diff(g[c])).max().unwrap_or(0);
                most = most.max(step);
            }
        }
        if count > 0 {
            differing.push((name, count, most));
        }
    }
    // Where wasm's maths library (Rust's libm) rounds a last bit otherwise
    // than glibc's: powf in the gamma at a code's step (one level of one
    // channel), sin and cos in the lens' and the lights' samples (a ray a
    // hair apart). A few pixels by a level; the book, guide/playground.md.
    let _ = writeln!(
        std::io::stderr(),
        "differing from their goldens: {differing:?}"
    );
    assert!(differing.iter().all(|d| d.2 <= 2), "{differing:?}");
    // A handful of pixels in all; the lab's tables (gamma 2.2) all equal.
    let total: usize = differing.iter().map(|d| d.1).sum();
    assert!(total <= 16, "{differing:?}");
    for (name, ..) in &differing {
        let lab = xtask::web::LAB_SCENES
            .iter()
            .any(|l| l.trim_end_matches(".toml") == name);
        assert!(!lab, "the lab's {name} differs: {differing:?}");
    }
}

/// Not a check: writes the book's screenshot, docs/src/images/playground.png
/// (`cargo test --release -p xtask --test web -- --ignored screenshot`).
#[test]
#[ignore]
fn screenshot_for_the_book() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    render_scene(&mut page, "textures.toml");
    // A mistake typed in: marked at its line, the last good image kept.
    let text = eval(&mut page, "tracerPage.view.state.doc.toString()");
    let bad = text
        .as_str()
        .unwrap()
        .replacen("fov = 55", "fov = 55\nfvo = 2", 1);
    type_text(&mut page, &bad);
    page.wait_for(
        "document.getElementById('image').dataset.state === 'error'",
        RENDER,
    )
    .unwrap();
    // The editor's marks are drawn on its next frame.
    std::thread::sleep(Duration::from_millis(500));
    let png = page.screenshot().unwrap();
    std::fs::write(
        xtask::workspace_root().join("docs/src/images/playground.png"),
        png,
    )
    .unwrap();
}

#[test]
fn an_edit_cancels_a_long_render() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    let text = editor_text(&mut page);
    // Minutes of work: 4096x4096 (the page's largest) at 4096 samples.
    let long = text
        .replacen("width = 500", "width = 4096", 1)
        .replacen("height = 400", "height = 4096", 1)
        .replacen("[render]", "[render]\nsamples = 4096", 1);
    type_text(&mut page, &long);
    // Past the debounce: the workers are busy with it.
    std::thread::sleep(Duration::from_secs(2));
    assert_eq!(
        eval(&mut page, "document.getElementById('image').dataset.state"),
        "rendering"
    );
    // Its preview (a quarter as wide) is shown at its own size: a canvas of
    // 4096x4096 would hold up the page while the image is still coming.
    page.wait_for("document.getElementById('image').width === 1024", RENDER)
        .unwrap();
    let start = std::time::Instant::now();
    type_text(&mut page, &text);
    wait_done(&mut page);
    // The long render's workers stopped at once: the next render runs alone.
    assert!(
        start.elapsed() < Duration::from_secs(5),
        "{:?}",
        start.elapsed()
    );
    assert_golden(&mut page, "reflectance2");
}

#[test]
fn a_dropped_json_scene_renders_as_its_toml() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    let root = xtask::workspace_root();
    let text = std::fs::read_to_string(root.join("scenes/reflectance2.toml")).unwrap();
    let value: toml::Value = toml::from_str(&text).unwrap();
    let json = serde_json::to_string_pretty(&value).unwrap();
    let files = serde_json::json!({ "final.json": json });
    eval(&mut page, &format!("tracerPage.addFiles({files})"));
    page.wait_for(
        "document.getElementById('status').textContent.startsWith('final.json: 500x400')",
        RENDER,
    )
    .unwrap();
    wait_done(&mut page);
    assert_golden(&mut page, "reflectance2");
    // The editor holds it, as JSON.
    let shown = eval(&mut page, "tracerPage.view.state.doc.toString()");
    assert_eq!(shown.as_str().unwrap(), json);
    let menu = eval(&mut page, "document.getElementById('scene-menu').value");
    assert_eq!(menu, "");
}

#[test]
fn a_dropped_gltf_with_its_bin_renders_as_tracer_render_and_its_mistake_is_located() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    let path = xtask::workspace_root().join("scenes/khronos/BoxTextured.gltf");
    let text = std::fs::read_to_string(&path).unwrap();
    // The model's buffer moved out to a .bin dropped along, as exporters write it.
    let dropped = format!(
        "(() => {{ const m = JSON.parse({}); const uri = m.buffers[0].uri; \
         const bin = Uint8Array.from(atob(uri.slice(uri.indexOf(',') + 1)), c => c.charCodeAt(0)); \
         m.buffers[0].uri = 'box.bin'; \
         tracerPage.addFiles({{'box.gltf': JSON.stringify(m, null, 2), 'box.bin': bin}}); }})()",
        serde_json::to_string(&text).unwrap()
    );
    eval(&mut page, &dropped);
    page.wait_for(
        "document.getElementById('status').textContent.startsWith('box.gltf: ')",
        RENDER,
    )
    .unwrap();
    wait_done(&mut page);
    let loaded = tracer_pipeline::load(&tracer_pipeline::Input::File(path)).unwrap();
    let rendered = tracer_pipeline::render(&loaded, &Default::default(), &|_| {}).unwrap();
    let rgb = rendered.image.to_rgb8();
    let shown = canvas_image(&mut page).unwrap();
    assert_eq!(shown.dimensions(), rgb.dimensions());
    assert!(
        rgb.pixels()
            .zip(shown.pixels())
            .all(|(a, b)| a.0 == b.0[..3]),
        "the page's render differs from tracer render's"
    );
    // The same model as one .glb (its JSON and its buffer in chunks), dropped alone.
    let glb = format!(
        "(() => {{ const m = JSON.parse({}); const uri = m.buffers[0].uri; \
         const bin = Uint8Array.from(atob(uri.slice(uri.indexOf(',') + 1)), c => c.charCodeAt(0)); \
         delete m.buffers[0].uri; \
         const pad = (b, fill) => {{ const p = new Uint8Array((b.length + 3) & ~3).fill(fill); p.set(b); return p; }}; \
         const json = pad(new TextEncoder().encode(JSON.stringify(m)), 0x20); const data = pad(bin, 0); \
         const out = new Uint8Array(12 + 8 + json.length + 8 + data.length); const v = new DataView(out.buffer); \
         v.setUint32(0, 0x46546C67, true); v.setUint32(4, 2, true); v.setUint32(8, out.length, true); \
         v.setUint32(12, json.length, true); v.setUint32(16, 0x4E4F534A, true); out.set(json, 20); \
         const at = 20 + json.length; v.setUint32(at, data.length, true); v.setUint32(at + 4, 0x004E4942, true); \
         out.set(data, at + 8); tracerPage.addFiles({{'box.glb': out}}); }})()",
        serde_json::to_string(&text).unwrap()
    );
    eval(&mut page, &glb);
    page.wait_for(
        "document.getElementById('status').textContent.startsWith('box.glb: ')",
        RENDER,
    )
    .unwrap();
    wait_done(&mut page);
    let shown = canvas_image(&mut page).unwrap();
    assert!(
        rgb.pixels()
            .zip(shown.pixels())
            .all(|(a, b)| a.0 == b.0[..3]),
        "the page's render of the .glb differs from tracer render's"
    );
    // A node index out of range: the error names the file and the JSON path.
    eval(
        &mut page,
        "tracerPage.addFiles({'broken.gltf': \
         '{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": [3]}]}'})",
    );
    page.wait_for(
        "document.getElementById('image').dataset.state === 'error'",
        RENDER,
    )
    .unwrap();
    let text = status(&mut page);
    assert!(
        text.contains("broken.gltf") && text.contains("scenes[0].nodes[0]"),
        "{text}"
    );
}

#[test]
fn a_click_on_the_image_explains_that_pixel_as_tracer_explain_does() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    render_scene(&mut page, "illumination.toml");
    // Shown at half its size: the click must be scaled to the image's pixels.
    let rect = eval(
        &mut page,
        "(() => { const c = document.getElementById('image'); c.style.width = '250px'; \
         c.scrollIntoView(); const r = c.getBoundingClientRect(); \
         return [r.left, r.top, r.width, r.height]; })()",
    );
    let rect: Vec<f64> = serde_json::from_value(rect).unwrap();
    assert_eq!(rect[2..], [250.0, 200.0], "{rect:?}");
    // At (215, 225), on the sphere's lit side (the light is to the lower
    // left). Chromium drops a click's fraction of a CSS pixel, two image
    // pixels wide here: the page may name a neighbour, but no farther.
    let at = |i: usize, p: f64| (rect[i] + (p + 0.5) / 2.0).round();
    let (cx, cy) = (at(0, 215.0), at(1, 225.0));
    for kind in ["mousePressed", "mouseReleased"] {
        page.call(
            "Input.dispatchMouseEvent",
            serde_json::json!({ "type": kind, "x": cx, "y": cy, "button": "left", "clickCount": 1 }),
        )
        .unwrap();
    }
    page.wait_for(
        "document.getElementById('explain').dataset.state === 'done'",
        RENDER,
    )
    .unwrap();
    let text = text_of(&mut page, "explain");
    let named = eval(
        &mut page,
        "document.getElementById('explain').dataset.pixel",
    );
    let (x, y): (u32, u32) = {
        let (x, y) = named.as_str().unwrap().split_once(',').unwrap();
        (x.parse().unwrap(), y.parse().unwrap())
    };
    // Unscaled, the click would name about (107, 112).
    assert!(x.abs_diff(215) <= 1 && y.abs_diff(225) <= 1, "({x}, {y})");
    // The text of `tracer explain`, which names the pixel once.
    assert!(
        text.starts_with(&format!("pixel ({x}, {y}) of illumination.toml (500x400;")),
        "{text}"
    );
    assert!(text.contains("nearest hit: objects[0]"), "{text}");
    // The pixel is marked where it is shown.
    let mark = eval(
        &mut page,
        "(() => { const m = document.getElementById('marker'); \
         const r = m.getBoundingClientRect(); \
         return [m.hidden, r.left + r.width / 2, r.top + r.height / 2]; })()",
    );
    assert_eq!(mark[0], false, "{mark}");
    let shown = |i: usize, p: u32| rect[i] + (f64::from(p) + 0.5) / 2.0;
    assert!(
        (mark[1].as_f64().unwrap() - shown(0, x)).abs() < 1.5,
        "{mark} {rect:?}"
    );
    assert!(
        (mark[2].as_f64().unwrap() - shown(1, y)).abs() < 1.5,
        "{mark} {rect:?}"
    );
    // Its 8-bit value is the pixel the page shows there.
    let [r, g, b, _] = canvas_image(&mut page).unwrap().get_pixel(x, y).0;
    assert!(r > 50, "not the lit sphere: ({r}, {g}, {b})");
    assert!(
        text.contains(&format!(
            "(int)(c * 255) = ({r}, {g}, {b}), the rendered pixel"
        )),
        "({r}, {g}, {b}) not in\n{text}"
    );
}

#[test]
fn a_scenes_warnings_show_under_the_image_and_at_their_line() {
    let Some(mut page) = open("?workers=1") else {
        return;
    };
    let good = editor_text(&mut page);
    // Colours on a 0-255 scale: rendered, and warned about as the CLI does.
    let warned = good.replacen("diffuse = [0, 0.6, 0]", "diffuse = [0, 153, 0]", 1);
    assert_ne!(warned, good);
    let line = warned.lines().position(|l| l.contains("153")).unwrap() + 1;
    type_text(&mut page, &warned);
    page.wait_for(
        "document.getElementById('image').dataset.state === 'done' && \
         document.getElementById('warnings').textContent.includes('0 to 255')",
        RENDER,
    )
    .unwrap();
    let text = text_of(&mut page, "warnings");
    assert!(
        text.starts_with("warning: reflectance2.toml: `materials."),
        "{text}"
    );
    let marked = eval(
        &mut page,
        "[...document.querySelectorAll('.cm-line')].findIndex(l => l.querySelector('.cm-lintRange-warning')) + 1",
    );
    assert_eq!(marked, Value::from(line));
    type_text(&mut page, &good);
    wait_done(&mut page);
    assert_eq!(text_of(&mut page, "warnings"), "");
    assert_golden(&mut page, "reflectance2");
}

#[test]
fn a_scene_asking_for_denoising_is_shown_as_rendered_with_a_note_why() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    render_scene(&mut page, "cornell-box.toml");
    let text = editor_text(&mut page);
    let asked = text.replacen("[render]\n", "[render]\ndenoise = true\n", 1);
    assert_ne!(asked, text);
    type_text(&mut page, &asked);
    page.wait_for(
        "document.getElementById('image').dataset.state === 'done' && \
         document.getElementById('warnings').textContent.includes('cannot denoise')",
        RENDER,
    )
    .unwrap();
    let warnings = text_of(&mut page, "warnings");
    assert!(warnings.contains("`render.denoise`"), "{warnings}");
}

#[test]
fn a_path_traced_render_shows_its_passes_and_stops_at_its_time_limit() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    render_scene(&mut page, "cornell-box.toml");
    assert_eq!(
        eval(&mut page, "tracerPage.lastRender.samples"),
        serde_json::json!([64, 64])
    );
    assert!(status(&mut page).contains("64 paths a pixel in"));
    let text = editor_text(&mut page);
    // Minutes of work at 4096 paths: the time limit stops it.
    let long = text.replacen("samples = 64", "samples = 4096\ntime_limit = 3", 1);
    assert_ne!(long, text);
    type_text(&mut page, &long);
    // While it runs, each pass is shown and counted, and the rows of the
    // pass under way.
    page.wait_for(
        "/paths a pixel so far, next pass [0-9]+ %/.test(document.getElementById('status').textContent)",
        RENDER,
    )
    .unwrap();
    page.wait_for(
        "document.getElementById('image').dataset.state === 'done' && \
         tracerPage.lastRender.samples[1] === 4096",
        RENDER,
    )
    .unwrap();
    let seconds = eval(&mut page, "tracerPage.lastRender.seconds");
    let samples = eval(&mut page, "tracerPage.lastRender.samples[0]");
    let samples = samples.as_u64().unwrap();
    assert!((1..4096).contains(&samples), "{samples}");
    assert!(samples.is_power_of_two(), "{samples}");
    // Stopped before a pass that would end past the limit (the page's own
    // time also counts its loading and preview).
    assert!(seconds.as_f64().unwrap() < 10.0, "{seconds}");
    let text = status(&mut page);
    assert!(
        text.contains(&format!("stopped at {samples} of 4096 paths a pixel")),
        "{text}"
    );
}

#[test]
fn another_sample_of_a_path_traced_pixel_is_explained_on_asking() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    render_scene(&mut page, "cornell-box.toml");
    // As after a click on (128, 64), then sample 5 asked for.
    eval(
        &mut page,
        "(() => { document.getElementById('explain').dataset.pixel = '128,64'; \
         const s = document.getElementById('explain-sample'); s.value = '5'; \
         s.dispatchEvent(new Event('change')); })()",
    );
    page.wait_for(
        "document.getElementById('explain').dataset.state === 'done'",
        RENDER,
    )
    .unwrap();
    let text = text_of(&mut page, "explain");
    assert!(
        text.starts_with("pixel (128, 64) of cornell-box.toml (256x256;"),
        "{text}"
    );
    assert!(text.contains("sample 5 of 64"), "{text}");
}

#[test]
fn undo_after_another_scene_is_chosen_never_brings_back_the_last_ones_text() {
    let Some(mut page) = open("?workers=1") else {
        return;
    };
    type_text(&mut page, "# mine\n");
    render_scene(&mut page, "shadows.toml");
    let shadows = editor_text(&mut page);
    eval(&mut page, "tracerPage.undo()");
    assert_eq!(editor_text(&mut page), shadows);
}

#[test]
fn stop_keeps_the_image_so_far_and_says_so() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    // A path-traced scene of many passes: stopped after its first.
    let text = std::fs::read_to_string(xtask::workspace_root().join("scenes/cornell-box.toml"))
        .unwrap()
        .replace("samples = 64", "samples = 65536");
    assert!(text.contains("samples = 65536"), "cornell-box.toml changed");
    type_text(&mut page, &text);
    page.wait_for(
        // A pass every band has: Stop keeps it.
        "/ [1-9][0-9]* of [0-9]+ paths a pixel so far/.test(document.getElementById('status').textContent)",
        RENDER,
    )
    .unwrap();
    assert_eq!(
        eval(&mut page, "document.getElementById('stop').disabled"),
        false
    );
    eval(&mut page, "document.getElementById('stop').click()");
    let state = eval(&mut page, "document.getElementById('image').dataset.state");
    assert_eq!(state, "stopped");
    let said = status(&mut page);
    assert!(said.contains("stopped at "), "{said}");
    assert!(said.contains(" of 65536 paths a pixel"), "{said}");
    assert_eq!(
        eval(&mut page, "document.getElementById('stop').disabled"),
        true
    );
    // Not black: the passes so far are shown.
    let shown = canvas_image(&mut page).unwrap();
    let lit = shown.pixels().filter(|p| p.0[0] > 40).count();
    assert!(lit > shown.pixels().len() / 4, "{lit} lit pixels");
}

#[test]
fn on_a_phone_the_editor_and_the_image_stack_without_sideways_scrolling() {
    let Some(mut page) = open("?workers=1") else {
        return;
    };
    let metrics = serde_json::json!({
        "width": 390, "height": 844, "deviceScaleFactor": 1, "mobile": true
    });
    page.call("Emulation.setDeviceMetricsOverride", metrics)
        .unwrap();
    let width = eval(&mut page, "document.documentElement.scrollWidth");
    assert!(width.as_f64().unwrap() <= 390.0, "scrollWidth {width}");
    // The image is shown at the page's width, under the editor.
    let image = eval(
        &mut page,
        "(() => { const r = document.getElementById('image').getBoundingClientRect(); \
         const e = document.getElementById('editor').getBoundingClientRect(); \
         return [r.width, r.top >= e.bottom]; })()",
    );
    assert!(image[0].as_f64().unwrap() > 300.0, "{image}");
    assert_eq!(image[1], true, "{image}");
}

/// Node.js (the page's bundler runs on it), or `None` with a notice; under
/// CI (`.ci/run` installs it) that fails instead.
fn node() -> Option<&'static str> {
    let found = std::process::Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return Some("node");
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "CI is set but node is missing (Debian: apt-get install nodejs)"
    );
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED: the share link's test needs node"
    );
    None
}

/// The page's share-link code itself (web/src/share.js), run by Node.js,
/// which has the browser's DecompressionStream: no browser needed.
#[test]
fn a_share_link_inflates_to_at_most_the_page_s_scene_limit() {
    let Some(node) = node() else {
        return;
    };
    let share = xtask::workspace_root().join("web/src/share.js");
    let url = format!("file://{}", share.display());
    // A link of about 90 KB whose text inflates to one byte more than the
    // limit (one of 2 MB inflated to 2 GB), and a scene's own link.
    let script = format!(
        r#"import {{ decodeShare, encodeShare, MAX_SCENE_BYTES }} from {url:?};
import zlib from "node:zlib";
const small = await decodeShare(await encodeShare("a.toml", "[camera]\nfov = 50\n"));
const packed = zlib.deflateRawSync(Buffer.alloc(MAX_SCENE_BYTES + 1, 32), {{ level: 9 }});
const big = await decodeShare(`scene=x.toml&text=${{packed.toString("base64url")}}`);
console.log(JSON.stringify({{ max: MAX_SCENE_BYTES, small, big, rss: process.memoryUsage().rss }}));
"#
    );
    let out = std::process::Command::new(node)
        .args(["--input-type=module", "-e", &script])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let result: Value = serde_json::from_slice(&out.stdout).unwrap();
    // The page's limit is the loader's limit of a scene file.
    assert_eq!(result["max"], scene_format::read::MAX_SCENE_BYTES);
    assert_eq!(result["small"]["name"], "a.toml");
    assert_eq!(result["small"]["text"], "[camera]\nfov = 50\n");
    let refused = result["big"]["refused"].as_str().unwrap_or_else(|| {
        panic!(
            "a link past the limit was opened: {:.200}",
            result["big"].to_string()
        )
    });
    assert!(refused.contains("over 64 MiB once inflated"), "{refused}");
}

/// With the book beside the page (`book/`, where `cargo xtask web` copies a
/// built one), the help link shows and opens the book's playground page.
#[test]
fn the_help_link_opens_the_books_playground_page_when_the_book_is_beside() {
    if chromium().is_none() {
        return;
    }
    let out = xtask::target_dir().join("web-test");
    let _ = page();
    let help = out.join("book/guide/playground.html");
    if !help.is_file() {
        std::fs::create_dir_all(help.parent().unwrap()).unwrap();
        std::fs::write(&help, "<h1>The playground</h1>").unwrap();
    }
    let mut browser = open("").unwrap();
    browser
        .wait_for("!document.getElementById('help').hidden", RENDER)
        .unwrap();
    let href = eval(&mut browser, "document.getElementById('help').href");
    assert!(
        href.as_str()
            .unwrap()
            .ends_with("/book/guide/playground.html"),
        "{href}"
    );
}

/// Clicks the image's pixel (x, y), as a user does, and waits for its
/// explanation; the pixel the page names and the canvas's box.
fn click_pixel(page: &mut Browser, (x, y): (u32, u32)) -> ((u32, u32), Vec<f64>) {
    let rect = eval(
        page,
        "(() => { const c = document.getElementById('image'); c.scrollIntoView(); \
         const r = c.getBoundingClientRect(); return [r.left, r.top, r.width, r.height, c.width, c.height]; })()",
    );
    let rect: Vec<f64> = serde_json::from_value(rect).unwrap();
    let at =
        |i: usize, p: u32| (rect[i] + (f64::from(p) + 0.5) * rect[i + 2] / rect[i + 4]).round();
    for kind in ["mousePressed", "mouseReleased"] {
        page.call(
            "Input.dispatchMouseEvent",
            serde_json::json!({ "type": kind, "x": at(0, x), "y": at(1, y), "button": "left", "clickCount": 1 }),
        )
        .unwrap();
    }
    page.wait_for(
        "document.getElementById('explain').dataset.state === 'done'",
        RENDER,
    )
    .unwrap();
    let named = eval(page, "document.getElementById('explain').dataset.pixel");
    let (nx, ny) = named.as_str().unwrap().split_once(',').unwrap();
    ((nx.parse().unwrap(), ny.parse().unwrap()), rect)
}

#[test]
fn a_click_draws_the_pixels_rays_its_first_hit_on_the_pixel_and_a_blocked_shadow_ray_dashed_red() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    // shadows.toml's pixel (100, 150): the wall, in the red ball's shadow
    // (`tracer explain` says: blocked by objects[1]).
    render_scene(&mut page, "shadows.toml");
    let ((x, y), rect) = click_pixel(&mut page, (100, 150));
    assert!(x.abs_diff(100) <= 1 && y.abs_diff(150) <= 1, "({x}, {y})");
    // The primary ray's hit ring is drawn centred on the pixel's centre,
    // where the canvas is now (the explanation's lines may have brought a
    // scroll bar and moved it).
    let now = eval(
        &mut page,
        "(() => { const c = document.getElementById('image').getBoundingClientRect(); \
         const r = document.querySelector('#rays g.ray[data-ray=\"0\"] circle.hit')\
         .getBoundingClientRect(); \
         return [c.left, c.top, c.width, c.height, r.left + r.width / 2, r.top + r.height / 2]; })()",
    );
    let now: Vec<f64> = serde_json::from_value(now).unwrap();
    let centre = |i: usize, p: u32| now[i] + (f64::from(p) + 0.5) * now[i + 2] / rect[i + 4];
    let ring = [now[4], now[5]];
    assert!(
        (ring[0] - centre(0, x)).abs() < 0.75 && (ring[1] - centre(1, y)).abs() < 0.75,
        "ring at {ring:?}, pixel ({x}, {y}) at ({}, {})",
        centre(0, x),
        centre(1, y)
    );
    // Its shadow ray: blocked, dashed, red, named by its blocker.
    let shadow = eval(
        &mut page,
        "(() => { const g = document.querySelector('#rays g.ray.shadow'); \
         const line = g.querySelector('line.stroke'); \
         return [g.classList.contains('blocked'), line.getAttribute('stroke-dasharray') || '', \
         getComputedStyle(line).stroke, g.querySelector('title').textContent, \
         g.querySelector('text.blocker').textContent]; })()",
    );
    assert_eq!(shadow[0], true, "{shadow}");
    assert!(!shadow[1].as_str().unwrap().is_empty(), "dashed: {shadow}");
    assert_eq!(shadow[2], "rgb(255, 40, 40)", "{shadow}");
    assert_eq!(shadow[3], "shadow ray to lights[0]: blocked by objects[1]");
    assert_eq!(shadow[4], "objects[1]");
    // Hovering the shadow ray's line of the explanation lights its ray.
    let hot = eval(
        &mut page,
        "(() => { const row = [...document.querySelectorAll('#explain .line')]\
         .find(r => r.textContent.startsWith('shadow ray from')); \
         row.dispatchEvent(new MouseEvent('mouseover', { bubbles: true })); \
         const ray = row.dataset.ray; \
         return [ray, document.querySelector(`#rays g.ray[data-ray=\"${ray}\"]`).classList.contains('hot')]; })()",
    );
    assert_eq!(hot[1], true, "{hot}");
}

#[test]
fn next_visits_every_step_of_the_explanation_once_in_order_and_back_returns() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    render_scene(&mut page, "reflectance2.toml");
    click_pixel(&mut page, (250, 330));
    // Next until it is disabled: each step once, in the text's order, its
    // lines (and only they) marked current.
    let walk = eval(
        &mut page,
        "(() => { const next = document.getElementById('step-next'); \
         const panel = document.getElementById('explain'); \
         const rows = [...panel.querySelectorAll('.line')]; \
         const steps = rows.map(r => Number(r.dataset.step)); \
         const visited = []; let wrong = 0; \
         while (!next.disabled && visited.length < 1000) { next.click(); \
           const s = Number(panel.dataset.step); visited.push(s); \
           const current = rows.filter(r => r.classList.contains('current')); \
           if (current.length === 0 || current.some(r => Number(r.dataset.step) !== s) \
               || current.length !== steps.filter(t => t === s).length) wrong += 1; } \
         return { steps, visited, wrong, lines: rows.length }; })()",
    );
    let steps: Vec<u64> = serde_json::from_value(walk["steps"].clone()).unwrap();
    let visited: Vec<u64> = serde_json::from_value(walk["visited"].clone()).unwrap();
    let count = steps.iter().max().unwrap() + 1;
    assert_eq!(visited, (0..count).collect::<Vec<_>>(), "{walk}");
    assert_eq!(walk["wrong"], 0, "{walk}");
    // The mirror ray's line is a step whose ray is drawn current then.
    let mirror = eval(
        &mut page,
        "(() => { const row = [...document.querySelectorAll('#explain .line')]\
         .find(r => r.textContent.startsWith('mirror ray from')); \
         const panel = document.getElementById('explain'); \
         while (Number(panel.dataset.step) > Number(row.dataset.step)) document.getElementById('step-back').click(); \
         const g = document.querySelector(`#rays g.ray[data-ray=\"${row.dataset.ray}\"]`); \
         return [row.classList.contains('current'), g.classList.contains('current'), g.classList.contains('reflected')]; })()",
    );
    assert_eq!(mirror, serde_json::json!([true, true, true]));
}

/// Not a check: writes the book's picture of a pixel's rays in the
/// playground, docs/src/images/playground-explain.png, stepped to its
/// mirror ray (`cargo test --release -p xtask --test web -- --ignored
/// screenshot`).
#[test]
#[ignore]
fn screenshot_of_a_pixels_rays_for_the_book() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    // A laptop's screen.
    let metrics = serde_json::json!({
        "width": 1280, "height": 900, "deviceScaleFactor": 1, "mobile": false
    });
    page.call("Emulation.setDeviceMetricsOverride", metrics)
        .unwrap();
    render_scene(&mut page, "reflectance2.toml");
    click_pixel(&mut page, (250, 330));
    eval(
        &mut page,
        "(() => { const row = [...document.querySelectorAll('#explain .line')]\
         .find(r => r.textContent.startsWith('mirror ray from')); \
         const panel = document.getElementById('explain'); \
         while (Number(panel.dataset.step) < Number(row.dataset.step)) \
           document.getElementById('step-next').click(); \
         window.scrollTo(0, 0); })()",
    );
    std::thread::sleep(Duration::from_millis(300));
    let png = page.screenshot().unwrap();
    std::fs::write(
        xtask::workspace_root().join("docs/src/images/playground-explain.png"),
        png,
    )
    .unwrap();
}

#[test]
fn the_3d_view_holds_as_many_objects_as_the_scene_and_follows_an_edit() {
    let Some(mut page) = open("?workers=2") else {
        return;
    };
    render_scene(&mut page, "reflectance2.toml");
    click_pixel(&mut page, (250, 330));
    let file =
        std::fs::read_to_string(xtask::workspace_root().join("scenes/reflectance2.toml")).unwrap();
    let objects = file.lines().filter(|l| l.trim() == "[[objects]]").count();
    let shown = eval(
        &mut page,
        "(() => { const v = document.getElementById('view3d'); \
         const c = v.querySelector('canvas'); \
         return [v.hidden, Number(v.dataset.objects), Number(v.dataset.rays), c.width > 0, \
         document.querySelectorAll('#rays g.ray').length]; })()",
    );
    assert_eq!(shown[0], false, "{shown}");
    assert_eq!(shown[1], objects, "{shown}");
    assert_eq!(
        shown[2], shown[4],
        "the same rays as over the image: {shown}"
    );
    // The 3D view's canvas is drawn: not one colour.
    let colours = eval(
        &mut page,
        "(() => { const c = document.querySelector('#view3d canvas'); \
         const g = c.getContext('webgl2') || c.getContext('webgl'); \
         const px = new Uint8Array(c.width * c.height * 4); \
         g.readPixels(0, 0, c.width, c.height, g.RGBA, g.UNSIGNED_BYTE, px); \
         const seen = new Set(); for (let k = 0; k < px.length; k += 4 * 97) seen.add(px[k] << 16 | px[k + 1] << 8 | px[k + 2]); \
         return seen.size; })()",
    );
    assert!(colours.as_u64().unwrap() > 20, "{colours}");
    // An object added to the file: the image renders again, and the view
    // and the explanation follow.
    let more = format!(
        "{file}\n[[objects]]\nsphere = {{ center = [3, 2, 0], radius = 0.5 }}\nmaterial = \"red\"\n"
    );
    type_text(&mut page, &more);
    page.wait_for(
        &format!(
            "Number(document.getElementById('view3d').dataset.objects) === {}",
            objects + 1
        ),
        RENDER,
    )
    .unwrap();
}
