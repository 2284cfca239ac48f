// The playground: an editor holding a scene file, the image the tracer's
// wasm renders of it in Web Workers, the scenes of scenes/ in a menu, files
// dropped in as the scene's folder, and links that carry the scene's text.

import { EditorView, basicSetup } from "codemirror";
import { EditorState } from "@codemirror/state";
import { StreamLanguage } from "@codemirror/language";
import { toml } from "@codemirror/legacy-modes/mode/toml";
import { json } from "@codemirror/lang-json";
import { setDiagnostics, lintGutter } from "@codemirror/lint";
import { undo } from "@codemirror/commands";
import { decodeShare, encodeShare } from "./share.js";
import { zip } from "./zip.js";
import { drawRays, legend } from "./rays.js";
import { showTree, linkHover, Stepper } from "./steps.js";
import { View3d } from "./view3d.js";

const DEBOUNCE_MS = 300;
// More workers than this give no speed and each holds a wasm instance.
const MAX_WORKERS = 16;
// After an image of more pixels than this, the workers are made anew: a
// wasm instance's memory never shrinks, and the next image may be small.
const RELEASE_PIXELS = 2048 * 2048;
const PREVIEW_SHRINK = 4;
// Above this many pixels a preview is not blown up to the image's size.
const HUGE_PIXELS = 2048 * 2048;

const menu = document.getElementById("scene-menu");
const canvas = document.getElementById("image");
const status = document.getElementById("status");
const warningsNote = document.getElementById("warnings");
const folderNote = document.getElementById("folder");
const explainPanel = document.getElementById("explain");
const explainSample = document.getElementById("explain-sample");
const stopButton = document.getElementById("stop");
const marker = document.getElementById("marker");
const raysOverlay = document.getElementById("rays");
const raysLegend = document.getElementById("rays-legend");
const stepBar = document.getElementById("steps");
const notice = document.getElementById("notice");
const params = new URLSearchParams(location.search);
// `?workers=N` (tests, the bench) overrides one worker per core.
const workerCount = Math.min(
  MAX_WORKERS,
  Math.max(1, Math.floor(Number(params.get("workers"))) || navigator.hardwareConcurrency || 1),
);

// The scene: its path in the folder (the name messages give it), and the
// folder's other files, path -> bytes. `archive` is set when the scene is
// a dropped `tracer pack` archive or .glb model, rendered as it is.
const scene = { name: "reflectance2.toml", files: new Map(), archive: null };
let scenesIndex = [];
let wasmModule = null;

const languageOf = (name) =>
  /\.(json|gltf)$/i.test(name) ? json() : StreamLanguage.define(toml);

// The editor's setup for a file `name`; typing re-renders.
const extensions = (name) => [
  basicSetup,
  EditorView.lineWrapping,
  lintGutter(),
  languageOf(name),
  EditorView.updateListener.of((update) => {
    if (update.docChanged) {
      opening += 1;
      if (scene.archive) {
        // The text typed over an archive's note is a scene of its own.
        scene.archive = null;
        scene.name = "scene.toml";
      }
      schedule();
    }
  }),
];

const view = new EditorView({
  parent: document.getElementById("editor"),
  state: EditorState.create({ doc: "", extensions: extensions(scene.name) }),
});

// Another file in the editor: a state of its own, so that undo never
// brings back another scene's text under this one's name.
function setText(text, name) {
  view.setState(EditorState.create({ doc: text, extensions: extensions(name) }));
}

// ---- Workers ----------------------------------------------------------

let pool = [];
let busy = false;
let generation = 0;

function makePool() {
  pool = Array.from({ length: workerCount }, () => {
    const worker = new Worker("worker.js", { type: "module" });
    worker.postMessage({ module: wasmModule });
    return worker;
  });
}

// Renders `job` (a region) in `worker`; resolves with the worker's answer,
// calling `on.pass` with each pass before the last (a path-traced render)
// and `on.rows` with the rows done of the pass under way.
function runJob(worker, job, on = {}) {
  return new Promise((resolve) => {
    worker.onmessage = (event) => {
      if (event.data.pass) on.pass?.(event.data.pass);
      else if (event.data.rows !== undefined) on.rows?.(event.data.rows);
      else resolve(event.data);
    };
    worker.postMessage(job);
  });
}

// Ends the render in flight: its workers are stopped mid-render.
function cancel() {
  generation += 1;
  stopButton.disabled = true;
  if (busy) {
    releaseMemory();
    busy = false;
  }
}

let timer = null;
function schedule() {
  clearTimeout(timer);
  cancel();
  canvas.dataset.state = "rendering";
  if (status.className !== "error") status.textContent = `${scene.name}: rendering…`;
  timer = setTimeout(render, DEBOUNCE_MS);
}

function folderFiles() {
  const files = [...scene.files];
  if (scene.archive) files.push([scene.name, scene.archive]);
  else files.push([scene.name, new TextEncoder().encode(view.state.doc.toString())]);
  return files;
}

// Bands of whole rows, as `tracer render --tile I/N` cuts them.
function bands(width, height, count) {
  const n = Math.max(1, Math.min(count, height));
  const row = (i) => Math.floor((i * height) / n);
  return Array.from({ length: n }, (_, i) => [0, row(i), width, row(i + 1)]);
}

async function render() {
  const mine = ++generation;
  busy = true;
  const files = folderFiles();
  const base = { scene: scene.name, files, samples: 0, panic: window.tracerPage.panicNext };
  window.tracerPage.panicNext = false;
  canvas.dataset.state = "rendering";
  // The quarter-size preview (one sample a pixel) tells the errors and the
  // image's size quickly; the full image follows across every worker.
  const preview = await runJob(pool[0], { ...base, id: mine, shrink: PREVIEW_SHRINK, samples: 1, region: null });
  if (mine !== generation) return;
  if (!preview.ok) return showError(preview.error);
  const pathTraced = preview.notes.path;
  showProblems([], preview.notes.warnings);
  const { fullWidth, fullHeight } = preview;
  imageSize = [fullWidth, fullHeight];
  // A huge image's canvas takes seconds of the page's own thread to make:
  // its preview is shown at its own size, the canvas made full size once
  // the full image is there (an edit meanwhile cancels it cheaply).
  const huge = fullWidth * fullHeight > HUGE_PIXELS;
  const [showWidth, showHeight] = huge ? [preview.width, preview.height] : [fullWidth, fullHeight];
  if (canvas.width !== showWidth || canvas.height !== showHeight) {
    canvas.width = showWidth;
    canvas.height = showHeight;
  }
  let ctx = canvas.getContext("2d");
  const small = new ImageData(new Uint8ClampedArray(preview.rgba), preview.width, preview.height);
  const bitmap = await createImageBitmap(small);
  if (mine !== generation) return;
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(bitmap, 0, 0, showWidth, showHeight);
  status.className = "";
  status.textContent = `${scene.name}: preview shown, rendering ${fullWidth}x${fullHeight} on ${pool.length} worker(s)…`;

  const start = performance.now();
  const regions = bands(fullWidth, fullHeight, pool.length);
  // A path-traced band comes in passes of doubling samples: each shown as
  // it comes, kept until every band has it, so that the image ends at the
  // samples all bands reached (a time limit may stop them apart).
  const passes = regions.map(() => new Map());
  const reached = regions.map(() => 0);
  // The share of each band's pass under way that is done.
  const partly = regions.map(() => 0);
  let total = 0;
  const showProgress = () => {
    const seconds = ((performance.now() - start) / 1000).toFixed(1);
    const least = Math.min(...reached);
    // A band past the slowest one's pass has done its share of it: the
    // share does not fall back when that band starts its next pass.
    const done = partly.reduce((sum, part, i) => sum + (reached[i] > least ? 1 : part), 0);
    const share = Math.floor((100 * done) / partly.length);
    let so = `${share} %`;
    if (pathTraced) so = total ? `${least} of ${total} paths a pixel so far, next pass ${share} %` : `first pass ${share} %`;
    status.textContent = `${scene.name}: rendering ${fullWidth}x${fullHeight} on ${pool.length} worker(s): ${so}, ${seconds} s…`;
  };
  // Every band shown at the pass all of them have.
  const showLeast = (least) =>
    regions.forEach((_, i) => {
      const pass = passes[i].get(least);
      if (pass && reached[i] !== least) draw(i, pass);
    });
  // Stop: the passes every band has are kept, the rest of the work dropped.
  stopRender = () => {
    const least = Math.min(...reached);
    cancel();
    showLeast(least);
    const kept = pathTraced && least > 0 ? ` at ${least} of ${total} paths a pixel` : " before its end (the image is partly rendered)";
    status.textContent = `${scene.name}: stopped${kept}`;
    canvas.dataset.state = "stopped";
  };
  stopButton.disabled = false;
  const draw = (i, rgba) => {
    if (huge && canvas.width !== fullWidth) {
      canvas.width = fullWidth;
      canvas.height = fullHeight;
      ctx = canvas.getContext("2d");
      // The preview, blown up, where no band is drawn yet.
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(bitmap, 0, 0, fullWidth, fullHeight);
    }
    const [x0, y0, x1, y1] = regions[i];
    ctx.putImageData(new ImageData(new Uint8ClampedArray(rgba), x1 - x0, y1 - y0), x0, y0);
  };
  const keep = (i, samples, rgba) => {
    passes[i].set(samples, rgba);
    reached[i] = samples;
    const least = Math.min(...reached);
    for (const band of passes) for (const s of band.keys()) if (s < least) band.delete(s);
  };
  const on = (i) => ({
    pass: (pass) => {
      if (mine !== generation) return;
      keep(i, pass.samples, pass.rgba);
      total = pass.total;
      partly[i] = 0;
      draw(i, pass.rgba);
      showProgress();
    },
    rows: (rows) => {
      if (mine !== generation) return;
      partly[i] = Math.min(1, rows / (regions[i][3] - regions[i][1]));
      showProgress();
    },
  });
  let rays = 0;
  const answers = await Promise.all(
    regions.map((region, i) =>
      runJob(pool[i], { ...base, id: mine, shrink: 0, region }, on(i)).then((answer) => {
        if (mine === generation && answer.ok) {
          keep(i, answer.notes.samples[0], answer.rgba);
          draw(i, answer.rgba);
          rays += answer.rays;
        }
        return answer;
      }),
    ),
  );
  if (mine !== generation) return;
  busy = false;
  stopButton.disabled = true;
  const failed = answers.find((a) => !a.ok);
  if (failed) return showError(failed.error);
  const [least, of] = [Math.min(...reached), answers[0].notes.samples[1]];
  showLeast(least);
  const seconds = (performance.now() - start) / 1000;
  const mrays = rays / seconds / 1e6;
  window.tracerPage.lastRender = {
    scene: scene.name,
    seconds,
    // The slowest worker's own time in the wasm (the bench's figure).
    workerSeconds: Math.max(...answers.map((a) => a.ms)) / 1000,
    rays,
    workers: regions.length,
    width: fullWidth,
    height: fullHeight,
    // Path mode: paths a pixel rendered, of the scene's.
    samples: pathTraced ? [least, of] : null,
  };
  const paths = pathTraced ? `, ${pathsAPixel(least)}` : "";
  // A canvas is drawn, not traced: no rays to count.
  const speed = rays > 0 ? `, ${mrays.toFixed(2)} Mrays/s` : "";
  let text = `${scene.name}: ${fullWidth}x${fullHeight}${paths} in ${seconds.toFixed(2)} s${speed} (${regions.length} worker${regions.length === 1 ? "" : "s"})`;
  if (pathTraced && least < of) {
    text += `\nstopped at ${least} of ${of} paths a pixel: the next pass would end after the scene's time_limit`;
  }
  status.textContent = text;
  explainSample.max = Math.max(0, of - 1);
  canvas.dataset.state = "done";
  window.tracerPage.renders += 1;
  if (fullWidth * fullHeight > RELEASE_PIXELS) releaseMemory();
  // The pixel explained follows the edit, as the image does: its tree,
  // its rays and the 3D view anew (its viewpoint kept).
  if (shownView && shownViewScene === scene.name && explainPanel.dataset.state === "done") {
    const [x, y] = explainPanel.dataset.pixel.split(",").map(Number);
    if (x < fullWidth && y < fullHeight) explainPixel(x, y);
  }
}

const pathsAPixel = (n) => `${n} path${n === 1 ? "" : "s"} a pixel`;

// The workers made anew, their memory given back to the system.
function releaseMemory() {
  pool.forEach((w) => w.terminate());
  makePool();
}

// What the Stop button does for the render under way.
let stopRender = () => {};
stopButton.addEventListener("click", () => {
  if (busy) stopRender();
});

// ---- Explain a pixel --------------------------------------------------

// The scene's image size (the canvas holds only a preview of a huge one).
let imageSize = null;
// Its own worker: a render's edit does not stop it, nor it a render.
let explainWorker = null;
let explainBusy = false;

// A click on the image: that pixel's tree, as `tracer explain` prints it.
canvas.addEventListener("click", (event) => {
  if (!wasmModule) return;
  // The canvas may be shown smaller than it is (CSS): scale the click to
  // the full image's pixels, (0, 0) its top-left.
  const rect = canvas.getBoundingClientRect();
  const [width, height] = imageSize || [canvas.width, canvas.height];
  const clamp = (v, n) => Math.min(n - 1, Math.max(0, Math.floor(v)));
  const x = clamp(((event.clientX - rect.left) / rect.width) * width, width);
  const y = clamp(((event.clientY - rect.top) / rect.height) * height, height);
  // Marked in shares of the image: it stays on the pixel however shown.
  marker.style.left = `${((x + 0.5) / width) * 100}%`;
  marker.style.top = `${((y + 0.5) / height) * 100}%`;
  marker.hidden = false;
  explainPixel(x, y);
});

// Another sample of the pixel explained (`tracer explain --sample K`).
explainSample.addEventListener("change", () => {
  const pixel = explainPanel.dataset.pixel;
  if (pixel) explainPixel(...pixel.split(",").map(Number));
});

async function explainPixel(x, y) {
  const sample = Math.max(0, Math.floor(Number(explainSample.value)) || 0);
  const asked = `${x},${y},${sample}`;
  // A click while one is explained starts afresh rather than waiting.
  if (explainBusy) explainWorker.terminate();
  if (explainBusy || !explainWorker) {
    explainWorker = new Worker("worker.js", { type: "module" });
    explainWorker.postMessage({ module: wasmModule });
  }
  explainBusy = true;
  explainPanel.dataset.pixel = `${x},${y}`;
  explainPanel.dataset.asked = asked;
  explainPanel.dataset.state = "computing";
  explainPanel.textContent = `Pixel (${x}, ${y}): explaining…`;
  const job = { scene: scene.name, files: folderFiles(), explain: [x, y], sample, view: true };
  const answer = await runJob(explainWorker, job);
  // A later click owns the panel now.
  if (explainPanel.dataset.asked !== asked || explainPanel.dataset.state !== "computing") return;
  explainBusy = false;
  explainPanel.dataset.state = answer.ok ? "done" : "error";
  // The text names the pixel; an error does not.
  // The page's sample box, not the command line's --sample.
  const why = answer.ok ? "" : answer.error.text.replace(/^--sample /, "sample ");
  if (!answer.ok) {
    explainPanel.textContent = `Pixel (${x}, ${y})\n\n${why}`;
    hideRays();
    return;
  }
  // Another pixel of the same scene keeps the 3D view's viewpoint.
  const sameScene = shownView !== null && shownViewScene === scene.name;
  shownView = answer.view;
  shownViewScene = scene.name;
  showTree(explainPanel, shownView.lines);
  drawRays(raysOverlay, shownView.drawing);
  view3d.show(shownView, sameScene);
  legend(raysLegend, shownView.drawing);
  stepBar.hidden = false;
  stepper.reset(shownView.lines);
}

// The explained pixel's lines and drawing, while shown, and its scene's name.
let shownView = null;
let shownViewScene = null;
const view3d = new View3d(document.getElementById("view3d"));
const stepper = new Stepper(
  explainPanel,
  raysOverlay,
  document.getElementById("step-back"),
  document.getElementById("step-next"),
  document.getElementById("step-where"),
  (rays) => view3d.highlight(rays),
);
linkHover(explainPanel, raysOverlay, (rays) => view3d.highlight(rays || stepper.rays));
// The marks keep their size on screen as the image's is changed.
new ResizeObserver(() => {
  if (shownView && !raysOverlay.hasAttribute("hidden")) {
    drawRays(raysOverlay, shownView.drawing);
    stepper.go(stepper.step);
  }
}).observe(canvas);

function hideRays() {
  shownView = null;
  raysOverlay.setAttribute("hidden", "");
  raysOverlay.replaceChildren();
  raysLegend.hidden = true;
  stepBar.hidden = true;
  view3d.hide();
}

// ---- Errors -----------------------------------------------------------

function showError(error) {
  busy = false;
  status.className = "error";
  status.textContent = error.text;
  canvas.dataset.state = "error";
  showProblems(error.problems, []);
}

// Marks each error and warning of the scene's own text at its line and
// column; the warnings (of any file) are listed under the status, as
// `tracer render` prints them.
function showProblems(errors, warnings) {
  warningsNote.textContent = warnings.map((w) => w.text).join("\n");
  const doc = view.state.doc;
  const mark = (severity) => (p) => {
    const line = doc.line(Math.min(p.line, doc.lines));
    const from = Math.min(line.from + Math.max(0, (p.column || 1) - 1), line.to);
    // The text the problem is about when it is on this line, else the
    // rest of the line.
    const end = p.end_line === p.line && p.end_column > p.column ? line.from + p.end_column - 1 : line.to;
    const to = Math.max(from + 1, Math.min(end, line.to, doc.length));
    return { from, to: Math.min(to, doc.length), severity, message: p.message };
  };
  const here = (p) => p.file === scene.name && p.line;
  const diagnostics = [
    ...errors.filter(here).map(mark("error")),
    ...warnings.filter(here).map(mark("warning")),
  ].sort((a, b) => a.from - b.from);
  view.dispatch(setDiagnostics(view.state, diagnostics));
}

// ---- Scenes, files ----------------------------------------------------

async function fetchBytes(path) {
  const response = await fetch(path);
  if (!response.ok) throw new Error(`${path}: ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

// The scene of the menu at `path` (under scenes/) with the files it reads.
// The latest scene asked for (a menu pick, a link, dropped files, an
// edit): an opening overtaken while it fetches is dropped.
let opening = 0;
async function openScene(path, text, mine = ++opening) {
  // The render in flight is the old scene's; not done until this one's is
  // (scripts wait on it).
  clearTimeout(timer);
  cancel();
  canvas.dataset.state = "rendering";
  const entry = scenesIndex.find((s) => s.path === path);
  const files = new Map();
  let body = text;
  try {
    await Promise.all(entry?.files.map(async (f) => files.set(f, await fetchBytes(`scenes/${f}`))) ?? []);
    body ??= new TextDecoder().decode(await fetchBytes(`scenes/${path}`));
  } catch (e) {
    if (mine !== opening) return;
    return showError({ text: `cannot open ${path}: ${e.message}`, problems: [] });
  }
  // Another scene was asked for meanwhile: it is the one shown.
  if (mine !== opening) return;
  scene.name = path;
  scene.files = files;
  scene.archive = null;
  menu.value = entry ? path : "";
  setText(body, path);
  resetExplain();
  showFolder();
  schedule();
}

function showFolder() {
  const names = [...scene.files.keys()];
  folderNote.textContent = names.length ? `Files of the scene: ${names.join(", ")}` : "";
}

// A glTF model is a scene of its own, rendered as `tracer render model.gltf`
// renders it (the wasm's pipeline reads it, with its .bin and images).
const SCENE_FILE = /\.(toml|json|gltf)$/i;

// Files dropped or picked: a scene file (or a `tracer pack` archive, or a
// binary .glb) among them starts a new folder; other files join the scene's
// folder (an archive holds its own).
async function addFiles(list) {
  opening += 1;
  const entries = await Promise.all(
    [...list].map(async (f) => [f.name, new Uint8Array(await f.arrayBuffer())]),
  );
  const zip = entries.find(([n]) => /\.(zip|glb)$/i.test(n));
  const sceneFile = entries.find(([n]) => SCENE_FILE.test(n));
  if (zip) {
    const glb = /\.glb$/i.test(zip[0]);
    scene.name = zip[0];
    scene.files = new Map(glb ? entries.filter(([n]) => n !== zip[0]) : []);
    scene.archive = zip[1];
    menu.value = "";
    const what = glb ? "a binary glTF model" : "a scene packed by `tracer pack`";
    setText(`# ${zip[0]}: ${what}, rendered as it is.\n# Edit here to render this text instead.\n`, "x.toml");
  } else {
    if (sceneFile) scene.files = new Map();
    for (const [name, bytes] of entries) {
      if (name !== sceneFile?.[0]) scene.files.set(name, bytes);
    }
    if (sceneFile) {
      scene.name = sceneFile[0];
      // A scene file dropped after an archive is the scene now, not the archive.
      scene.archive = null;
      menu.value = "";
      setText(new TextDecoder().decode(sceneFile[1]), sceneFile[0]);
    }
  }
  if (zip || sceneFile) resetExplain();
  showFolder();
  schedule();
}

// Another scene: the last one's explained pixel and sample are not its.
function resetExplain() {
  if (explainBusy) {
    explainWorker.terminate();
    explainWorker = null;
  }
  explainBusy = false;
  delete explainPanel.dataset.pixel;
  delete explainPanel.dataset.asked;
  delete explainPanel.dataset.state;
  explainPanel.textContent = "Click the image to see why a pixel has its colour.";
  explainSample.value = 0;
  marker.hidden = true;
  hideRays();
  notice.textContent = "";
}

document.getElementById("pick-files").addEventListener("change", (e) => addFiles(e.target.files));
document.addEventListener("dragover", (e) => {
  e.preventDefault();
  document.body.classList.add("dragging");
});
document.addEventListener("dragleave", () => document.body.classList.remove("dragging"));
document.addEventListener("drop", (e) => {
  e.preventDefault();
  document.body.classList.remove("dragging");
  addFiles(e.dataTransfer.files);
});

menu.addEventListener("change", () => {
  // The address no longer holds the scene shown (and the same link pasted
  // again is then a change the page hears of).
  history.replaceState(null, "", `${location.pathname}${location.search}`);
  openScene(menu.value);
});

// ---- Share, download --------------------------------------------------

document.getElementById("share").addEventListener("click", async () => {
  const text = view.state.doc.toString();
  const link = `${location.origin}${location.pathname}${location.search}#${await encodeShare(scene.name, text)}`;
  document.getElementById("share").dataset.link = link;
  history.replaceState(null, "", link);
  const own = scenesIndex.find((s) => s.path === scene.name);
  const extra = [...scene.files.keys()].filter((f) => !own || !own.files.includes(f));
  let note = "Link copied: it holds the scene's text.";
  if (scene.archive || extra.length) {
    note = "Link copied, but it holds only the scene's text: this scene reads files the link cannot carry; share it as a .zip instead (Download .zip).";
  }
  try {
    await navigator.clipboard.writeText(link);
  } catch {
    note = `Copy this link: ${link}`;
  }
  if (canvas.dataset.state !== "error") status.textContent = note;
});

document.getElementById("download-png").addEventListener("click", () => {
  canvas.toBlob((blob) => download(blob, `${stem()}.png`), "image/png");
});

// The scene as a `tracer pack` archive: its text, its files, the manifest.
// A dropped archive is itself.
function sceneZip() {
  if (scene.archive) return scene.archive;
  const manifest = `scene = ${JSON.stringify(scene.name)}\n`;
  return zip([["tracer-pack.toml", new TextEncoder().encode(manifest)], ...folderFiles()]);
}

function download(blob, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

const stem = () => scene.name.replace(/^.*\//, "").replace(/\.[^.]*$/, "");

document.getElementById("download-zip").addEventListener("click", () =>
  download(new Blob([sceneZip()], { type: "application/zip" }), `${stem()}.zip`),
);

// ---- Start ------------------------------------------------------------

window.tracerPage = {
  view,
  // For tests: the editor's Undo (Ctrl-Z).
  undo: () => undo(view),
  renders: 0,
  lastRender: null,
  // For tests: the next render's workers panic inside the wasm.
  panicNext: false,
  // For tests and scripts: files put into the scene's folder as if dropped.
  addFiles: (files) =>
    addFiles(Object.entries(files).map(([name, text]) => new File([text], name))),
  // The scene's archive, base64 (what Download .zip saves).
  sceneZipBase64: () => {
    let s = "";
    for (const b of sceneZip()) s += String.fromCharCode(b);
    return btoa(s);
  },
};

// The help link opens the book's page of the playground, when the book is
// served beside the page (`book/`, as `cargo xtask web` copies it there);
// without it the link would lead nowhere, so it stays hidden.
const helpLink = document.getElementById("help");
fetch(helpLink.getAttribute("href"), { cache: "no-store" })
  .then((r) => {
    if (r.ok) helpLink.hidden = false;
  })
  .catch(() => {});

async function start() {
  [wasmModule, scenesIndex] = await Promise.all([
    // Bytes first: compileStreaming refuses a server that does not call
    // the file application/wasm, and some static servers do not.
    fetch("tracer_web.wasm")
      .then((r) => r.arrayBuffer())
      .then((bytes) => WebAssembly.compile(bytes)),
    fetch("scenes/index.json").then((r) => r.json()),
  ]);
  for (const s of scenesIndex) {
    const option = document.createElement("option");
    option.value = s.path;
    option.textContent = s.lab ? `${s.path} (lab)` : s.path_traced ? `${s.path} (path traced)` : s.path;
    menu.append(option);
  }
  const other = document.createElement("option");
  other.value = "";
  other.textContent = "(your scene)";
  menu.append(other);
  makePool();
  const startHash = location.hash;
  if (!(await openShared())) await openScene("reflectance2.toml");
  if (location.hash.length > 1 && !opened) {
    notice.textContent = `${linkUnread()}: the default scene is shown.`;
  }
  started = true;
  // A link pasted while the page started.
  if (location.hash !== startHash && location.hash.length > 1) openShared();
}

// The scene of a share link in the address bar; false when there is none,
// it cannot be read or it is refused (`refused` then says why).
let opened = false;
let refused = "";
async function openShared() {
  const mine = ++opening;
  const shared = location.hash.length > 1 ? await decodeShare(location.hash.slice(1)) : null;
  if (mine !== opening) return true;
  refused = shared?.refused ?? "";
  opened = Boolean(shared) && !refused;
  if (opened) await openScene(shared.name, shared.text, mine);
  return opened;
}

// Why the link in the address bar was not opened.
function linkUnread() {
  return refused
    ? `This link's scene was not opened: ${refused}`
    : "This link's scene could not be read (is the link cut short?)";
}

// A link pasted into this tab's address bar changes only the fragment
// (heard once the page has started: it opens the first link itself).
let started = false;
window.addEventListener("hashchange", async () => {
  if (!started) return;
  if (!(await openShared()) && location.hash.length > 1) {
    notice.textContent = `${linkUnread()}.`;
  }
});

start().catch((e) => {
  status.className = "error";
  status.textContent = `The page could not start: ${e}`;
  canvas.dataset.state = "error";
});
