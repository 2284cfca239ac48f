//! `tracer watch` as a user runs it: edits of the scene and of its OBJ
//! file re-render it, a bad edit keeps the last image, Ctrl-C leaves no
//! temporary file.

use headless::Browser;
use local_server::test_client;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

/// The scene: a camera looking at a triangle of the OBJ, one light; the
/// triangle's colour comes from `diffuse`. With `samples` > 1 the light is
/// a sphere sampled 4096 times per sample: minutes of work.
fn scene(diffuse: [f32; 3], samples: u32) -> String {
    let radius = if samples > 1 { 0.01 } else { 0.0 };
    format!(
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 64\nheight = 48\n\
         [render]\nsamples = {samples}\nlight_samples = 4096\n\
         [[lights]]\nposition = [0, 0, 5]\nradius = {radius}\n\
         [[objects]]\nmesh = {{ obj = \"tri.obj\" }}\n\
         material = {{ diffuse = [{}, {}, {}] }}\n",
        diffuse[0], diffuse[1], diffuse[2]
    )
}

/// A triangle facing the camera, covering the image's centre; `x` moves
/// its right-hand vertex.
fn obj(x: f32) -> String {
    format!("v -3 -3 0\nv 3 -3 0\nv {x} 3 0\nf 1 2 3\n")
}

/// A running `tracer watch`, its stderr read line by line; killed when dropped.
struct Watching {
    child: Child,
    lines: Receiver<String>,
    seen: Vec<String>,
}

impl Watching {
    fn start(dir: &Path) -> Watching {
        Watching::start_with(dir, &[])
    }

    fn start_with(dir: &Path, more: &[&str]) -> Watching {
        let args = ["watch", "scene.toml", "-o", "out.png", "--threads", "1"];
        Watching::spawn(dir, &[&args[..], more].concat())
    }

    /// `tracer` with `args` in `dir`.
    fn spawn(dir: &Path, args: &[&str]) -> Watching {
        let mut child = Command::new(env!("CARGO_BIN_EXE_tracer"))
            .args(args)
            .current_dir(dir)
            .stderr(Stdio::piped())
            .spawn()
            .expect("run tracer watch");
        let stderr = child.stderr.take().expect("stderr");
        let (send, lines) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if send.send(line).is_err() {
                    break;
                }
            }
        });
        Watching {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// Waits up to `limit` for a line containing `text`.
    fn expect_line(&mut self, text: &str, limit: Duration) {
        let end = Instant::now() + limit;
        while let Some(left) = end.checked_duration_since(Instant::now()) {
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    let found = line.contains(text);
                    self.seen.push(line);
                    if found {
                        return;
                    }
                }
                Err(_) => break,
            }
        }
        panic!(
            "no line with {text:?} within {limit:?}; stderr:\n{}",
            self.seen.join("\n")
        );
    }
}

impl Drop for Watching {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Which channels of the centre pixel are lit (the lab's diffuse term is
/// just under the colour there: the pixel's ray is not quite on the axis).
fn centre_pixel(path: &Path) -> [bool; 3] {
    let image = image::open(path).expect("the output").to_rgb8();
    image.get_pixel(32, 24).0.map(|c| c > 200)
}

fn write(path: PathBuf, text: &str) {
    // Written whole and renamed in, as editors save.
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text).unwrap();
    std::fs::rename(&tmp, &path).unwrap();
}

/// What a render is given before the test decides it was missed: the issue
/// asks for a new image within 2 s of an edit.
const WITHIN: Duration = Duration::from_secs(2);
/// The first render also starts the process.
const START: Duration = Duration::from_secs(20);

#[test]
fn an_edit_renders_again_and_a_bad_edit_keeps_the_last_image() {
    let dir = tempfile::tempdir().unwrap();
    let (scene_path, out) = (dir.path().join("scene.toml"), dir.path().join("out.png"));
    write(dir.path().join("tri.obj"), &obj(0.0));
    write(scene_path.clone(), &scene([1.0, 0.0, 0.0], 1));
    let mut watching = Watching::start(dir.path());
    watching.expect_line("rendered", START);
    // Light and eye on the axis: the lab's diffuse term is the colour.
    assert_eq!(centre_pixel(&out), [true, false, false]);

    write(scene_path.clone(), &scene([0.0, 1.0, 0.0], 1));
    watching.expect_line("rendered", WITHIN);
    assert_eq!(centre_pixel(&out), [false, true, false]);

    write(
        scene_path.clone(),
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 500\n",
    );
    watching.expect_line("scene.toml:4:7", WITHIN);
    watching.expect_line("keeping the last good image", WITHIN);
    assert_eq!(centre_pixel(&out), [false, true, false]);

    // Fixed: rendered again.
    write(scene_path, &scene([0.0, 0.0, 1.0], 1));
    watching.expect_line("rendered", WITHIN);
    assert_eq!(centre_pixel(&out), [false, false, true]);
}

#[test]
fn an_edit_of_the_obj_alone_renders_again() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    write(dir.path().join("tri.obj"), &obj(0.0));
    write(dir.path().join("scene.toml"), &scene([1.0, 1.0, 1.0], 1));
    let mut watching = Watching::start(dir.path());
    watching.expect_line("rendered", START);
    assert_eq!(centre_pixel(&out), [true, true, true]);
    // The triangle moved away from the centre: the background shows.
    write(dir.path().join("tri.obj"), &obj(-20.0));
    watching.expect_line("rendered", WITHIN);
    assert_eq!(centre_pixel(&out), [false, false, false]);
}

/// `tracer watch` in a new folder, its preview done and its full render
/// begun: 4096 samples per pixel on 1 thread, far longer than a test waits.
fn watching_a_long_render() -> (tempfile::TempDir, Watching) {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path().join("tri.obj"), &obj(0.0));
    write(dir.path().join("scene.toml"), &scene([1.0, 0.0, 0.0], 4096));
    let mut watching = Watching::start(dir.path());
    watching.expect_line("preview", START);
    (dir, watching)
}

#[test]
fn an_edit_cancels_a_long_render() {
    let (dir, mut watching) = watching_a_long_render();
    let out = dir.path().join("out.png");
    write(dir.path().join("scene.toml"), &scene([0.0, 1.0, 0.0], 1));
    watching.expect_line("rendered", WITHIN);
    assert_eq!(centre_pixel(&out), [false, true, false]);
}

#[cfg(unix)]
#[test]
fn ctrl_c_ends_it_without_a_temporary_file() {
    let (dir, mut watching) = watching_a_long_render();
    let pid = watching.child.id().to_string();
    let killed = Command::new("kill").args(["-INT", &pid]).status().unwrap();
    assert!(killed.success());
    let status = watching.child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["out.png", "scene.toml", "tri.obj"]);
}

/// `tracer watch --serve` on a free port; the port it took.
fn serving(dir: &Path) -> (Watching, u16) {
    let mut watching = Watching::start_with(dir, &["--serve", "127.0.0.1:0"]);
    watching.expect_line("the live page: http://127.0.0.1:", START);
    let line = watching.seen.last().expect("the line").clone();
    let port = line
        .rsplit(':')
        .next()
        .and_then(|p| p.trim_end_matches('/').parse().ok())
        .unwrap_or_else(|| panic!("no port in {line:?}"));
    (watching, port)
}

/// The status line of the answer to `request` from the server on `port`,
/// sent raw (as a client that does not clean its path up would).
fn status_of(port: u16, request: &[u8]) -> String {
    test_client::status_of(([127, 0, 0, 1], port).into(), request)
}

/// A red triangle's scene in a new folder, watched with `--serve`, its
/// first render done; the scene file's path and the server's port.
fn serving_a_scene() -> (tempfile::TempDir, PathBuf, Watching, u16) {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("scene.toml");
    write(dir.path().join("tri.obj"), &obj(0.0));
    write(scene_path.clone(), &scene([1.0, 0.0, 0.0], 1));
    let (mut watching, port) = serving(dir.path());
    watching.expect_line("rendered", START);
    (dir, scene_path, watching, port)
}

/// A GET of `path` from the server on `port`, as a browser sends it.
fn get(port: u16, path: &str) -> Vec<u8> {
    test_client::get(&format!("127.0.0.1:{port}"), path)
}

#[test]
fn the_server_serves_the_page_image_and_events_and_nothing_else() {
    let (dir, _, _watching, port) = serving_a_scene();
    std::fs::write(dir.path().join("secret.txt"), "not to be served").unwrap();
    assert_eq!(status_of(port, &get(port, "/")), "HTTP/1.1 200 OK");
    assert_eq!(status_of(port, &get(port, "/image.png")), "HTTP/1.1 200 OK");
    for path in [
        "/../../etc/passwd",
        "/%2e%2e/%2e%2e/etc/passwd",
        "/%2E%2E%2F%2E%2E%2Fetc%2Fpasswd",
        "/image.png/../../etc/passwd",
        "/..%5c..%5cetc%5cpasswd",
        "/secret.txt",
        "/scene.toml",
        "//etc/passwd",
    ] {
        assert_eq!(
            status_of(port, &get(port, path)),
            "HTTP/1.1 404 Not Found",
            "{path}"
        );
    }
    let post = format!("POST / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Length: 3\r\nConnection: close\r\n\r\nabc");
    assert_eq!(
        status_of(port, post.as_bytes()),
        "HTTP/1.1 405 Method Not Allowed"
    );
    let body = format!("GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Length: 3\r\nConnection: close\r\n\r\nabc");
    assert_eq!(
        status_of(port, body.as_bytes()),
        "HTTP/1.1 413 Payload Too Large"
    );
    let huge = format!(
        "GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Big: {}\r\nConnection: close\r\n\r\n",
        "a".repeat(100_000)
    );
    let refused = status_of(port, huge.as_bytes());
    assert!(
        !refused.contains("200"),
        "an oversized head was served: {refused}"
    );
    // Still serving after the refusals.
    assert_eq!(status_of(port, &get(port, "/")), "HTTP/1.1 200 OK");
}

#[test]
fn the_live_page_answers_only_requests_to_its_own_address() {
    let (_dir, _, _watching, port) = serving_a_scene();
    // A page of another site whose name was rebound to 127.0.0.1 names
    // that site: it must not read the image or the scene's numbers.
    for path in ["/", "/image.png", "/events", "/explain?x=32&y=24"] {
        for host in [
            format!("attacker.example:{port}"),
            "attacker.example".to_string(),
        ] {
            assert_eq!(
                status_of(port, &test_client::get(&host, path)),
                "HTTP/1.1 421 Misdirected Request",
                "{host} {path}"
            );
        }
    }
    for host in [format!("127.0.0.1:{port}"), format!("localhost:{port}")] {
        for path in ["/", "/image.png", "/explain?x=32&y=24"] {
            assert_eq!(
                status_of(port, &test_client::get(&host, path)),
                "HTTP/1.1 200 OK",
                "{host} {path}"
            );
        }
    }
}

#[test]
fn a_vanished_or_silent_client_does_not_stall_rendering() {
    use std::io::Write;
    let (dir, scene_path, mut watching, port) = serving_a_scene();
    // Event streams never read, and connections that never finish their
    // request: more than the server serves at once.
    let mut idle = Vec::new();
    for k in 0..40 {
        let mut stream = std::net::TcpStream::connect(("127.0.0.1", port)).expect("connect");
        if k % 2 == 0 {
            let _ = stream.write_all(&get(port, "/events"));
        } else {
            let _ = stream.write_all(b"GET / HTTP/1.1\r\n");
        }
        idle.push(stream);
    }
    for colour in [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]] {
        write(scene_path.clone(), &scene(colour, 1));
        watching.expect_line("rendered", WITHIN);
    }
    assert_eq!(
        centre_pixel(&dir.path().join("out.png")),
        [true, true, true]
    );
}

/// Headless Chromium showing `url`, driven over its DevTools socket: the
/// test reads the live page's DOM while the page stays open. None when
/// there is no Chromium (an error on CI).
fn open_page(url: &str) -> Option<Browser> {
    let chromium = headless::chromium_for_test("the live page's test")?;
    Some(Browser::open(&chromium, url).expect("Chromium shows the page"))
}

#[test]
fn the_page_shows_each_render_and_the_error_without_a_reload() {
    let (_dir, scene_path, _watching, port) = serving_a_scene();
    let Some(mut page) = open_page(&format!("http://127.0.0.1:{port}/")) else {
        return;
    };
    page.wait_for("document.body.dataset.renders === '1'", START)
        .unwrap();
    let red = "(() => { const c = document.createElement('canvas'); const i = byId('image'); \
               c.width = i.naturalWidth; c.height = i.naturalHeight; \
               const g = c.getContext('2d'); g.drawImage(i, 0, 0); \
               return Array.from(g.getImageData(32, 24, 1, 1).data.slice(0, 3)); })()";
    page.wait_for(
        "byId('image').complete && byId('image').naturalWidth === 64",
        WITHIN,
    )
    .unwrap();
    let lit = |v: serde_json::Value| -> Vec<bool> {
        v.as_array()
            .expect("rgb")
            .iter()
            .map(|c| c.as_u64().unwrap() > 200)
            .collect()
    };
    assert_eq!(lit(page.eval(red).unwrap()), [true, false, false]);

    // An edit: the page gets the preview and the full render, no reload.
    write(scene_path.clone(), &scene([0.0, 1.0, 0.0], 1));
    page.wait_for("document.body.dataset.renders === '3'", WITHIN)
        .unwrap();
    page.wait_for(
        "byId('image').complete && byId('image').src.endsWith('render=3')",
        WITHIN,
    )
    .unwrap();
    assert_eq!(lit(page.eval(red).unwrap()), [false, true, false]);
    assert_eq!(page.eval("document.body.dataset.error").unwrap(), "hidden");

    // A bad edit: the error as `tracer check` prints it, the image kept.
    write(
        scene_path.clone(),
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 500\n",
    );
    page.wait_for("document.body.dataset.error === 'shown'", WITHIN)
        .unwrap();
    let error = page.eval("byId('error').textContent").unwrap();
    let error = error.as_str().expect("text");
    assert!(error.contains("scene.toml:4:7"), "{error}");
    assert!(error.contains("fov = 500"), "{error}");
    assert_eq!(page.eval("document.body.dataset.renders").unwrap(), "3");
    assert_eq!(lit(page.eval(red).unwrap()), [false, true, false]);

    // Fixed: the panel goes, the new image comes.
    write(scene_path, &scene([0.0, 0.0, 1.0], 1));
    page.wait_for("document.body.dataset.renders === '5'", WITHIN)
        .unwrap();
    assert_eq!(page.eval("document.body.dataset.error").unwrap(), "hidden");
}

#[test]
fn fixing_a_bad_included_file_renders_again() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    let lib = dir.path().join("lib.toml");
    let material = |colour: &str| format!("[materials.paint]\ndiffuse = {colour}\n");
    write(dir.path().join("tri.obj"), &obj(0.0));
    write(lib.clone(), &material("[1, 0, 0]"));
    let scene = "include = [\"lib.toml\"]\n\
                 [camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 64\nheight = 48\n\
                 [[lights]]\nposition = [0, 0, 5]\n\
                 [[objects]]\nmesh = { obj = \"tri.obj\" }\nmaterial = \"paint\"\n";
    write(dir.path().join("scene.toml"), scene);
    let mut watching = Watching::start(dir.path());
    watching.expect_line("rendered", START);
    assert_eq!(centre_pixel(&out), [true, false, false]);
    // A mistake in the included file: located there, the image kept.
    write(lib.clone(), &material("[1, 0]"));
    watching.expect_line("lib.toml:2:11", WITHIN);
    watching.expect_line("keeping the last good image", WITHIN);
    // Fixed in the included file: rendered again.
    write(lib, &material("[0, 0, 1]"));
    watching.expect_line("rendered", WITHIN);
    assert_eq!(centre_pixel(&out), [false, false, true]);
}

#[test]
fn an_output_that_is_a_texture_the_scene_reads_is_not_written() {
    let dir = tempfile::tempdir().unwrap();
    let texture = dir.path().join("wood.png");
    image::RgbImage::from_pixel(2, 2, image::Rgb([90, 60, 30]))
        .save(&texture)
        .unwrap();
    let before = std::fs::read(&texture).unwrap();
    write(dir.path().join("tri.obj"), &obj(0.0));
    let scene = scene([1.0, 1.0, 1.0], 1).replace(
        "material = { diffuse = [1, 1, 1] }",
        "material = { diffuse = [1, 1, 1], texture = { image = \"wood.png\" } }",
    );
    assert!(scene.contains("wood.png"), "{scene}");
    write(dir.path().join("scene.toml"), &scene);
    let mut watching = Watching::spawn(dir.path(), &["watch", "scene.toml", "-o", "wood.png"]);
    watching.expect_line("refusing to overwrite", START);
    assert_eq!(std::fs::read(&texture).unwrap(), before);
}

#[test]
fn a_path_traced_scene_is_shown_pass_by_pass_and_an_edit_stops_it() {
    // The Cornell box at 64 paths a pixel on one thread: passes of 1, 2,
    // 4, ... samples, each written whole; an edit starts again at once.
    let dir = tempfile::tempdir().unwrap();
    let cornell = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml"),
    )
    .unwrap();
    let small = cornell
        .replace("width = 256", "width = 48")
        .replace("height = 256", "height = 48");
    write(dir.path().join("scene.toml"), &small);
    let mut watching = Watching::start(dir.path());
    watching.expect_line("1 of 64 samples a pixel", START);
    watching.expect_line("2 of 64 samples a pixel", START);
    watching.expect_line("rendered", START);
    assert!(image::open(dir.path().join("out.png")).is_ok());
    // A long render, stopped by an edit within the time an edit is given.
    write(
        dir.path().join("scene.toml"),
        &small.replace("samples = 64", "samples = 65536"),
    );
    watching.expect_line("4 of 65536 samples a pixel", WITHIN);
    write(dir.path().join("scene.toml"), &small);
    watching.expect_line("1 of 64 samples a pixel", WITHIN);
    watching.expect_line("rendered", START);
    // A time limit is not watch's: said, and every pass rendered.
    write(
        dir.path().join("scene.toml"),
        &small.replace("samples = 64", "samples = 64\ntime_limit = 0.01"),
    );
    watching.expect_line("the scene's time_limit (0.01 s) is not used here", WITHIN);
    watching.expect_line("32 of 64 samples a pixel", START);
    watching.expect_line("rendered", START);
}

#[test]
fn a_click_on_the_live_page_shows_that_pixel_s_tree() {
    let (_dir, _scene_path, _watching, port) = serving_a_scene();
    // The endpoint alone: a pixel's tree, a bad query refused.
    assert_eq!(
        status_of(port, &get(port, "/explain?x=32&y=24")),
        "HTTP/1.1 200 OK"
    );
    assert_eq!(
        status_of(port, &get(port, "/explain?x=a&y=2")),
        "HTTP/1.1 400 Bad Request"
    );
    assert_eq!(
        status_of(port, &get(port, "/explain?x=640&y=2")),
        "HTTP/1.1 422 Unprocessable Entity"
    );
    let Some(mut page) = open_page(&format!("http://127.0.0.1:{port}/")) else {
        return;
    };
    page.wait_for(
        "byId('image').complete && byId('image').naturalWidth === 64",
        START,
    )
    .unwrap();
    // A click in pixel (32, 24) (the image is shown at its own size;
    // Chromium rounds a click's coordinates to whole CSS pixels).
    page.eval(
        "(() => { const i = byId('image'); const r = i.getBoundingClientRect(); \
         i.dispatchEvent(new MouseEvent('click', { clientX: Math.ceil(r.left + 32), clientY: Math.ceil(r.top + 24), bubbles: true })); })()",
    )
    .unwrap();
    page.wait_for("document.body.dataset.explained === '32,24'", WITHIN)
        .unwrap();
    let tree = page.eval("byId('explain').textContent").unwrap();
    let tree = tree.as_str().expect("text");
    assert!(
        tree.contains("pixel (32, 24)") && tree.contains("primary ray"),
        "{tree}"
    );
    assert!(tree.contains("N.L"), "{tree}");
}

/// Asserts that GET `path` is answered 200 within 2 seconds.
fn assert_served_within_2_s(port: u16, path: &str) {
    let asked = std::time::Instant::now();
    assert_eq!(status_of(port, &get(port, path)), "HTTP/1.1 200 OK");
    assert!(
        asked.elapsed() < Duration::from_secs(2),
        "{path}: {:?}",
        asked.elapsed()
    );
}

#[test]
fn idle_slow_and_never_reading_clients_do_not_starve_the_page() {
    use std::io::{Read, Write};
    let (_dir, _, _watching, port) = serving_a_scene();
    let connect = || std::net::TcpStream::connect(("127.0.0.1", port)).expect("connect");
    let mut held = Vec::new();
    // Idle connections, more than the old limit of 32 by far.
    for _ in 0..200 {
        held.push(connect());
    }
    // Clients sending their head a byte at a time, and event streams never read.
    let mut slow = Vec::new();
    for _ in 0..100 {
        let mut stream = connect();
        let _ = stream.write_all(b"G");
        slow.push(stream);
    }
    for _ in 0..40 {
        let mut stream = connect();
        let _ = stream.write_all(&get(port, "/events"));
        held.push(stream);
    }
    assert_served_within_2_s(port, "/");
    // A byte a second does not keep a slow head open past its timeout.
    for second in 0..5 {
        std::thread::sleep(Duration::from_secs(1));
        for stream in &mut slow {
            let _ = stream.write_all(if second % 2 == 0 { b"E" } else { b"T" });
        }
    }
    let mut closed = 0;
    for stream in held.iter_mut().take(200).chain(&mut slow) {
        stream
            .set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
        let mut byte = [0u8; 1];
        // Closed by the server: end of stream or reset; open: a timeout.
        match stream.read(&mut byte) {
            Ok(0) => closed += 1,
            Err(e) if e.kind() == std::io::ErrorKind::ConnectionReset => closed += 1,
            _ => {}
        }
    }
    assert_eq!(closed, 300, "idle and slow connections left open");
    assert_served_within_2_s(port, "/image.png");
}
