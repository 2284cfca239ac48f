//! The tracer in a browser tab: the pipeline's load, render and explain
//! behind a small C ABI, for `wasm32-unknown-unknown` (`cargo xtask web`).
//!
//! Why a hand-written ABI and not wasm-bindgen: the page needs half a dozen
//! calls that pass bytes (files in, RGBA or JSON out); wasm-bindgen would
//! need its `wasm-bindgen-cli` at exactly the crate's version, installed
//! with `cargo install` (minutes of build on these machines, and a second
//! pin to keep in step), for no gain here.
//!
//! The page owns memory it passes in through [`tracer_alloc`] /
//! [`tracer_free`]; a call's answer (RGBA pixels, an explained pixel's
//! text, or an error as JSON) stays in this module's result buffer until
//! the next call ([`tracer_result_ptr`], [`tracer_result_len`]). One instance runs one
//! call at a time (a Web Worker each): no threads inside the wasm.

use scene_format::source::{Archive, Memory, Source};
use std::cell::RefCell;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use tracer_pipeline::{Loaded, Options, Part, Region, Summary};

mod answer;
mod page;
pub use answer::error_json;

/// What one instance holds between calls.
#[derive(Default)]
struct State {
    /// The scene's folder, as the page gave it.
    files: Memory,
    /// The last call's answer.
    result: Vec<u8>,
    /// The size of the last image rendered, of the scene's full image,
    /// and the rays traced.
    size: (u32, u32),
    full: (u32, u32),
    rays: f64,
    /// The last render's samples a pixel, of the scene's, whether path
    /// traced, and its warnings: JSON for the page ([`tracer_notes_ptr`]).
    notes: String,
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

/// A buffer of `len` bytes for the page to fill; give it back with
/// [`tracer_free`].
#[no_mangle]
pub extern "C" fn tracer_alloc(len: usize) -> *mut u8 {
    Box::into_raw(vec![0u8; len].into_boxed_slice()).cast()
}

/// Frees a buffer of [`tracer_alloc`].
///
/// # Safety
/// `ptr` and `len` are those of one buffer of `tracer_alloc`, freed once.
#[no_mangle]
pub unsafe extern "C" fn tracer_free(ptr: *mut u8, len: usize) {
    // SAFETY: the caller passes back a boxed slice made by tracer_alloc.
    drop(unsafe { Box::from_raw(std::ptr::slice_from_raw_parts_mut(ptr, len)) });
}

/// Empties the scene's folder.
#[no_mangle]
pub extern "C" fn tracer_clear_files() {
    STATE.with_borrow_mut(|s| s.files = Memory::new());
}

/// Adds a file to the scene's folder at `path` (UTF-8, relative); 0 when
/// done, 1 with the error's JSON as the result.
///
/// # Safety
/// The pointers and lengths are those of buffers of `tracer_alloc`.
#[no_mangle]
pub unsafe extern "C" fn tracer_add_file(
    path: *const u8,
    path_len: usize,
    data: *const u8,
    data_len: usize,
) -> u32 {
    // SAFETY: as the caller promises.
    let (path, data) = unsafe { (bytes(path, path_len), bytes(data, data_len)) };
    let path = String::from_utf8_lossy(path).into_owned();
    let added = STATE.with_borrow_mut(|s| s.files.insert(Path::new(&path), data.to_vec()));
    match added {
        Ok(()) => 0,
        Err(e) => fail(answer::message_json(&format!("{path}: {e}"))),
    }
}

/// Loads the scene file at `path` of the folder and renders the pixels
/// `x0..x1` by `y0..y1` of its image (all of it when `x1` is 0), as
/// `tracer render` makes them; `shrink`, when above 1, renders the same
/// view that many times narrower (a preview), and `samples` (when not 0)
/// overrides the samples a pixel. 0 with the region's RGBA pixels as the
/// result; 1 with the error's JSON. The image's size is then
/// [`tracer_width`] x [`tracer_height`], the scene's
/// [`tracer_full_width`] x [`tracer_full_height`].
///
/// # Safety
/// `path`, `path_len` are those of a buffer of `tracer_alloc`.
#[no_mangle]
pub unsafe extern "C" fn tracer_render(
    path: *const u8,
    path_len: usize,
    shrink: u32,
    samples: u32,
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
) -> u32 {
    // SAFETY: as the caller promises.
    let path = String::from_utf8_lossy(unsafe { bytes(path, path_len) }).into_owned();
    let request = Request {
        shrink: (shrink > 1).then_some(shrink),
        samples: (samples > 0).then_some(samples),
        region: (x1 > 0).then_some(Region { x0, y0, x1, y1 }),
    };
    let mut clock = page::PassClock::new();
    let mut on_pass = |pass: PassImage| clock.pass(&pass);
    let done =
        STATE.with_borrow(|s| render_passes(&s.files, Path::new(&path), &request, &mut on_pass));
    match done {
        Ok(image) => STATE.with_borrow_mut(|s| {
            s.size = image.size;
            s.full = image.full;
            s.rays = image.rays as f64;
            s.notes = answer::notes_json(image.samples, image.path_traced, &image.warnings);
            s.result = image.rgba;
            0
        }),
        Err(json) => fail(json),
    }
}

/// Loads the scene file at `path` of the folder and explains pixel (x, y)
/// of its image at its full size (x from the left, y from the top),
/// tracing its sample `sample`: the text `tracer explain SCENE X Y
/// --sample K` prints, by the pipeline's one formatter.
/// 0 with the text (UTF-8) as the result; 1 with the error's JSON.
///
/// # Safety
/// `path`, `path_len` are those of a buffer of `tracer_alloc`.
#[no_mangle]
pub unsafe extern "C" fn tracer_explain(
    path: *const u8,
    path_len: usize,
    x: u32,
    y: u32,
    sample: u32,
) -> u32 {
    // SAFETY: as the caller promises.
    let path = unsafe { bytes(path, path_len) };
    answer_explained(path, (x, y), sample, explain)
}

/// As [`tracer_explain`], with the text's lines and the rays to draw as
/// JSON ([`explain_view`]): what the page shows.
///
/// # Safety
/// `path`, `path_len` are those of a buffer of `tracer_alloc`.
#[no_mangle]
pub unsafe extern "C" fn tracer_explain_view(
    path: *const u8,
    path_len: usize,
    x: u32,
    y: u32,
    sample: u32,
) -> u32 {
    // SAFETY: as the caller promises.
    let path = unsafe { bytes(path, path_len) };
    answer_explained(path, (x, y), sample, explain_view)
}

/// [`explain`] or [`explain_view`]: a pixel's sample of a scene of the
/// files, answered, or the error's JSON.
type Explainer = fn(&Memory, &Path, (u32, u32), u32) -> Result<String, String>;

/// `answer_of` pixel `at`'s sample `sample` of the scene at `path` (the
/// text, or the page's view): 0 with it as the result, or 1 with the
/// error's JSON.
fn answer_explained(path: &[u8], at: (u32, u32), sample: u32, answer_of: Explainer) -> u32 {
    let path = String::from_utf8_lossy(path).into_owned();
    match STATE.with_borrow(|s| answer_of(&s.files, Path::new(&path), at, sample)) {
        Ok(answer) => STATE.with_borrow_mut(|s| {
            s.result = answer.into_bytes();
            0
        }),
        Err(json) => fail(json),
    }
}

/// The width of the last render's image.
#[no_mangle]
pub extern "C" fn tracer_width() -> u32 {
    STATE.with_borrow(|s| s.size.0)
}

/// The height of the last render's image.
#[no_mangle]
pub extern "C" fn tracer_height() -> u32 {
    STATE.with_borrow(|s| s.size.1)
}

/// The width of the last render's scene at its own size.
#[no_mangle]
pub extern "C" fn tracer_full_width() -> u32 {
    STATE.with_borrow(|s| s.full.0)
}

/// The height of the last render's scene at its own size.
#[no_mangle]
pub extern "C" fn tracer_full_height() -> u32 {
    STATE.with_borrow(|s| s.full.1)
}

/// The rays the last render traced (primary, shadow, reflected...).
#[no_mangle]
pub extern "C" fn tracer_rays() -> f64 {
    STATE.with_borrow(|s| s.rays)
}

/// Where the last render's notes are: JSON, `{"samples": [done, of],
/// "path": bool, "warnings": [...]}` (`path` when path traced; each
/// warning as an error's problem, with its `text` as `tracer render`
/// prints it).
#[no_mangle]
pub extern "C" fn tracer_notes_ptr() -> *const u8 {
    STATE.with_borrow(|s| s.notes.as_ptr())
}

/// How long the last render's notes are.
#[no_mangle]
pub extern "C" fn tracer_notes_len() -> usize {
    STATE.with_borrow(|s| s.notes.len())
}

/// Where the last call's answer is.
#[no_mangle]
pub extern "C" fn tracer_result_ptr() -> *const u8 {
    STATE.with_borrow(|s| s.result.as_ptr())
}

/// How long the last call's answer is.
#[no_mangle]
pub extern "C" fn tracer_result_len() -> usize {
    STATE.with_borrow(|s| s.result.len())
}

/// # Safety
/// As for `std::slice::from_raw_parts`; a null or empty buffer is empty.
unsafe fn bytes<'a>(ptr: *const u8, len: usize) -> &'a [u8] {
    if ptr.is_null() || len == 0 {
        return &[];
    }
    // SAFETY: as the caller promises.
    unsafe { std::slice::from_raw_parts(ptr, len) }
}

fn fail(json: String) -> u32 {
    STATE.with_borrow_mut(|s| s.result = json.into_bytes());
    1
}

/// What to render of a scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct Request {
    /// A preview: the image this many times narrower (the height follows).
    pub shrink: Option<u32>,
    pub samples: Option<u32>,
    /// The pixels to render; the whole image when None.
    pub region: Option<Region>,
}

/// A region rendered: its RGBA pixels (alpha 255), the image's size, the
/// scene's own size, the rays traced, the samples a pixel it has of the
/// scene's, and the scene's warnings.
#[derive(Debug, Clone)]
pub struct RegionImage {
    pub rgba: Vec<u8>,
    pub size: (u32, u32),
    pub full: (u32, u32),
    pub rays: u64,
    pub samples: (u32, u32),
    pub path_traced: bool,
    pub warnings: Vec<tracer_pipeline::Warning>,
}

/// A pass of a render in passes (path mode): the region's RGBA pixels so
/// far, its samples a pixel so far and of all.
#[derive(Debug, Clone)]
pub struct PassImage<'a> {
    pub rgba: &'a [u8],
    pub samples: u32,
    pub total: u32,
    /// The scene's `[render] time_limit`, in seconds.
    pub time_limit: Option<f64>,
}

/// Loads the scene at `path` of `files` (a `.zip` from `tracer pack`
/// holds its own folder) and renders `request`'s region through the
/// pipeline; an error as the page's JSON.
pub fn render(files: &Memory, path: &Path, request: &Request) -> Result<RegionImage, String> {
    render_passes(files, path, request, &mut |_| true)
}

/// [`render`] in passes, as `tracer render` renders a path-traced scene:
/// samples 0..1, 1..2, 2..4, ..., `on_pass` called after each with the
/// region so far (false stops there: the image then has the samples of
/// that pass). A preview, a canvas and a scene in Whitted mode are one
/// pass. The last pass is `render`'s image bit for bit.
pub fn render_passes(
    files: &Memory,
    path: &Path,
    request: &Request,
    on_pass: &mut dyn FnMut(PassImage) -> bool,
) -> Result<RegionImage, String> {
    let loaded = load(files, path)?;
    let is_canvas = matches!(loaded.kind, scene_format::SceneKind::Canvas(_));
    let full = loaded.size();
    too_large_for_the_page(&loaded, full)?;
    // Said of the render the user asked for, not of the preview's samples.
    let warnings = loaded.warning_list(&Options::default());
    let mut options = Options::default();
    if !is_canvas {
        options.width = request.shrink.map(|k| (full.0 / k).max(1));
        options.samples = request.samples;
    }
    let size = tracer_pipeline::image_size(&loaded, &options).map_err(|e| error_json(&e))?;
    let region = request.region.unwrap_or(Region {
        x0: 0,
        y0: 0,
        x1: size.0,
        y1: size.1,
    });
    // Checked here for a canvas too, which is cropped below.
    let region = Part::Region(region)
        .region(size)
        .map_err(|e| error_json(&e))?;
    // A canvas is drawn whole (it takes no region, and is quick); a 3D
    // scene renders only its region, whose pixels are the whole image's.
    let crop = if is_canvas {
        (region.x0, region.y0)
    } else {
        (0, 0)
    };
    let crop = Crop { at: crop, region };
    let shown = if is_canvas || request.shrink.is_some() {
        if !is_canvas {
            options.part = Some(Part::Region(region));
        }
        let rendered =
            tracer_pipeline::render(&loaded, &options, &|_| {}).map_err(|e| error_json(&e))?;
        let rgb = rendered.image.to_rgb8();
        Shown {
            rgba: crop.rgba(rgb.as_raw(), rgb.width()),
            rays: rays_of(&rendered),
            samples: (1, 1),
        }
    } else {
        options.part = Some(Part::Region(region));
        in_passes(&loaded, &options, &crop, on_pass)?
    };
    Ok(RegionImage {
        rgba: shown.rgba,
        size,
        full,
        rays: shown.rays,
        samples: shown.samples,
        path_traced: loaded.is_path_traced(&options),
        warnings,
    })
}

/// The most pixels the page renders: a tab holds the image several times
/// over (each worker's part and its passes, the canvas, the preview), and
/// a wasm instance's memory never shrinks. `tracer render` goes to 16384
/// a side.
pub const MAX_PAGE_PIXELS: u64 = 4096 * 4096;

/// An error at the scene's `width` when its image is larger than the page
/// renders, placed in the scene file as a mistake of it is.
fn too_large_for_the_page(loaded: &Loaded, (w, h): (u32, u32)) -> Result<(), String> {
    if u64::from(w) * u64::from(h) <= MAX_PAGE_PIXELS {
        return Ok(());
    }
    let table = match loaded.kind {
        scene_format::SceneKind::Canvas(_) => "canvas",
        scene_format::SceneKind::Scene3d(_) => "camera",
    };
    let message = format!(
        "{w}x{h} is more than the playground renders (at most 4096x4096, 16.8 million \
         pixels, which a browser tab holds several times over); expected smaller `width` \
         and `height` here, or `tracer render` for the full size (up to 16384 a side)"
    );
    let diagnostic = scene_format::Diagnostic::new(format!("{table}.width"), message);
    let error = match loaded.origins.files.first() {
        Some(file) => {
            scene_format::checks::invalid(&loaded.name, &file.text, file.format, vec![diagnostic])
        }
        None => return Err(answer::message_json(&diagnostic.message)),
    };
    Err(error_json(&tracer_pipeline::Error::Scene(error)))
}

/// What a render made of its region: its pixels (RGBA), its rays, and
/// its samples a pixel of all.
struct Shown {
    rgba: Vec<u8>,
    rays: u64,
    samples: (u32, u32),
}

/// The rays a render traced (none for a canvas).
fn rays_of(rendered: &tracer_pipeline::Rendered) -> u64 {
    match &rendered.summary {
        Summary::Shaded(stats) => stats.rays,
        _ => 0,
    }
}

/// A 3D scene's region rendered in passes, shown by its last pass's
/// pixels (the image's: they are not made again).
fn in_passes(
    loaded: &Loaded,
    options: &Options,
    crop: &Crop,
    on_pass: &mut dyn FnMut(PassImage) -> bool,
) -> Result<Shown, String> {
    let never = AtomicBool::new(false);
    let mut samples = (0, 0);
    let mut last = Vec::new();
    let mut each = |pass: tracer_pipeline::Pass| {
        samples = (pass.samples, pass.total);
        let rgb = pass.picture.to_rgb8();
        last = crop.rgba(rgb.as_raw(), rgb.width());
        on_pass(PassImage {
            rgba: &last,
            samples: pass.samples,
            total: pass.total,
            time_limit: loaded.time_limit(),
        })
    };
    let passes = (&page::rows_done as &(dyn Fn(u32) + Sync), &mut each as _);
    let rendered = tracer_pipeline::render_progressive(loaded, options, "the page", &never, passes)
        .map_err(|e| error_json(&e))?
        .expect("never cancelled");
    Ok(Shown {
        rgba: last,
        rays: rays_of(&rendered),
        samples,
    })
}

/// Which pixels of a rendered image the page gets: `region`, found at
/// `at` in the image (a canvas is drawn whole; a 3D region is the image).
struct Crop {
    at: (u32, u32),
    region: Region,
}

impl Crop {
    /// The region's pixels of an RGB image `width` wide, as RGBA with
    /// alpha 255.
    fn rgba(&self, rgb: &[u8], width: u32) -> Vec<u8> {
        let (x_off, y_off) = self.at;
        let (w, h) = (
            self.region.x1 - self.region.x0,
            self.region.y1 - self.region.y0,
        );
        let mut rgba = Vec::with_capacity((w * h * 4) as usize);
        let row_bytes = width as usize * 3;
        for row in rgb
            .chunks_exact(row_bytes)
            .skip(y_off as usize)
            .take(h as usize)
        {
            let row = &row[x_off as usize * 3..(x_off + w) as usize * 3];
            for p in row.chunks_exact(3) {
                rgba.extend_from_slice(&[p[0], p[1], p[2], 255]);
            }
        }
        rgba
    }
}

/// Pixel (x, y) of the scene at `path` of `files` explained, its sample
/// `sample`, as `tracer explain --sample` prints it (its default options:
/// the scene's own size and samples); an error as the page's JSON.
pub fn explain(
    files: &Memory,
    path: &Path,
    (x, y): (u32, u32),
    sample: u32,
) -> Result<String, String> {
    explained(files, path, (x, y), sample).map(|(text, _)| text)
}

/// [`explain`]'s text as the page shows it, and what it draws: JSON,
/// `{"lines": [...], "drawing": {...}, "scene": {...}}`, each line of the
/// text with its depth, step, lab section and ray
/// (`explain_steps::Line`), the drawing `tracer explain --json` gives
/// (`explain_draw::Drawing`), and the scene's shapes and camera for the 3D
/// view (`explain_scene::SceneView`).
pub fn explain_view(
    files: &Memory,
    path: &Path,
    (x, y): (u32, u32),
    sample: u32,
) -> Result<String, String> {
    let (text, pixel) = explained(files, path, (x, y), sample)?;
    let lines = tracer_pipeline::explain_steps::lines(&text, &pixel);
    let view = serde_json::json!({
        "lines": lines,
        "drawing": pixel.drawing,
        "scene": pixel.scene_view,
    });
    Ok(view.to_string())
}

/// The text of [`explain`] and the explained pixel.
fn explained(
    files: &Memory,
    path: &Path,
    (x, y): (u32, u32),
    sample: u32,
) -> Result<(String, tracer_pipeline::explain::ExplainedPixel), String> {
    let loaded = load(files, path)?;
    let options = Options::default();
    let pixel = tracer_pipeline::explain::explain(&loaded, &options, (x, y), sample)
        .map_err(|e| error_json(&e))?;
    let text =
        tracer_pipeline::explain_text::text(&pixel, (x, y), &loaded.name.display().to_string());
    // The page's render stops at the scene's time limit; this traces every
    // sample, as `tracer explain` says on its stderr.
    let text = match loaded.time_limit_not_kept(&options) {
        Some(limit) => format!(
            "note: the scene's time_limit ({limit} s) is not used here: the pixel is the mean of \
             all its samples, where the image shown may have stopped at fewer\n{text}"
        ),
        _ => text,
    };
    Ok((text, pixel))
}

/// The scene at `path`: from the folder, or from the archive `path` is.
fn load(files: &Memory, path: &Path) -> Result<Loaded, String> {
    let is_zip = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("zip"));
    let scene_error = |e| error_json(&tracer_pipeline::Error::Scene(e));
    if !is_zip {
        return tracer_pipeline::load_from(files, path).map_err(scene_error);
    }
    let bytes = files
        .read(path, scene_format::source::MAX_ARCHIVE_BYTES)
        .map_err(|e| answer::message_json(&format!("{}: {e}", path.display())))?;
    let archive = Archive::from_bytes(path, bytes)
        .map_err(|e| answer::message_json(&format!("{}: {e}", path.display())))?;
    tracer_pipeline::load_from(&archive, archive.scene()).map_err(scene_error)
}

/// Panics: the page's tests check that a panic shows as an error and that
/// the next render works (the worker makes a fresh instance).
#[no_mangle]
pub extern "C" fn tracer_panic() {
    panic!("a panic asked for by tracer_panic");
}

#[cfg(target_arch = "wasm32")]
mod panic {
    #[link(wasm_import_module = "env")]
    extern "C" {
        /// The page's record of a panic's message, before the trap.
        fn tracer_panicked(ptr: *const u8, len: usize);
    }

    /// The panic's message goes to the page (a trap alone says nothing).
    #[no_mangle]
    pub extern "C" fn tracer_init() {
        std::panic::set_hook(Box::new(|info| {
            let text = info.to_string();
            // SAFETY: the page reads the bytes during the call.
            unsafe { tracer_panicked(text.as_ptr(), text.len()) };
        }));
    }
}
