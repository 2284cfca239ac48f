// One render worker: an instance of the tracer's wasm (crates/web) that
// renders one region of a scene per message, or explains one pixel. A panic inside the wasm traps;
// the instance is then dropped and the next job makes a fresh one.

let module = null;
let instance = null;
let panicked = null;
// The job being rendered: its passes are posted with its id.
let jobId = null;

function fresh() {
  panicked = null;
  const imports = {
    env: {
      tracer_panicked(ptr, len) {
        const bytes = new Uint8Array(instance.exports.memory.buffer, ptr >>> 0, len >>> 0);
        panicked = new TextDecoder().decode(bytes.slice());
      },
      tracer_now_ms: () => performance.now(),
      // A pass of a path-traced render, its region's pixels so far: shown
      // while the next pass runs.
      tracer_pass(samples, total, ptr, len) {
        const rgba = new Uint8Array(instance.exports.memory.buffer, ptr >>> 0, len >>> 0).slice().buffer;
        self.postMessage({ id: jobId, pass: { samples, total, rgba } }, [rgba]);
      },
      // Rows of the region done in the pass under way (a few times a second).
      tracer_rows(rows) {
        self.postMessage({ id: jobId, rows });
      },
    },
  };
  instance = new WebAssembly.Instance(module, imports);
  instance.exports.tracer_init();
  return instance.exports;
}

// wasm32's pointers and sizes are unsigned; JavaScript reads an i32
// result as signed, so one past 2 GiB of memory would be negative.
const u32 = (n) => n >>> 0;

// Copies `bytes` into a buffer of the wasm's memory.
function put(t, bytes) {
  const ptr = u32(t.tracer_alloc(bytes.length));
  new Uint8Array(t.memory.buffer, ptr, bytes.length).set(bytes);
  return [ptr, bytes.length];
}

function result(t) {
  return new Uint8Array(t.memory.buffer, u32(t.tracer_result_ptr()), u32(t.tracer_result_len())).slice();
}

function run(job) {
  const t = instance ? instance.exports : fresh();
  if (job.panic) t.tracer_panic();
  t.tracer_clear_files();
  const buffers = [];
  try {
    for (const [path, bytes] of job.files) {
      const p = put(t, new TextEncoder().encode(path));
      const d = put(t, bytes);
      buffers.push(p, d);
      if (t.tracer_add_file(p[0], p[1], d[0], d[1]) !== 0) {
        return { ok: false, error: JSON.parse(new TextDecoder().decode(result(t))) };
      }
    }
    const name = put(t, new TextEncoder().encode(job.scene));
    buffers.push(name);
    if (job.explain) {
      // One pixel's tree, as `tracer explain` prints it.
      const [x, y] = job.explain;
      // With `view`: its lines and the rays to draw, as JSON.
      const call = job.view ? t.tracer_explain_view : t.tracer_explain;
      const rc = call(name[0], name[1], x, y, job.sample || 0);
      const answer = new TextDecoder().decode(result(t));
      if (rc !== 0) return { ok: false, error: JSON.parse(answer) };
      return job.view ? { ok: true, view: JSON.parse(answer) } : { ok: true, text: answer };
    }
    const [x0, y0, x1, y1] = job.region || [0, 0, 0, 0];
    jobId = job.id;
    const start = performance.now();
    const rc = t.tracer_render(name[0], name[1], job.shrink, job.samples, x0, y0, x1, y1);
    const ms = performance.now() - start;
    if (rc !== 0) {
      return { ok: false, error: JSON.parse(new TextDecoder().decode(result(t))) };
    }
    const notes = new Uint8Array(t.memory.buffer, u32(t.tracer_notes_ptr()), u32(t.tracer_notes_len()));
    return {
      ok: true,
      // Samples a pixel [done, of the scene's], whether path traced, warnings.
      notes: JSON.parse(new TextDecoder().decode(notes.slice())),
      rgba: result(t).buffer,
      width: t.tracer_width(),
      height: t.tracer_height(),
      fullWidth: t.tracer_full_width(),
      fullHeight: t.tracer_full_height(),
      rays: t.tracer_rays(),
      ms,
    };
  } catch (e) {
    instance = null;
    throw e;
  } finally {
    // A trapped instance is not used again, so its buffers need no freeing.
    if (instance) {
      for (const [ptr, len] of buffers) t.tracer_free(ptr, len);
    }
  }
}

self.onmessage = (event) => {
  const message = event.data;
  if (message.module) {
    module = message.module;
    return;
  }
  let answer;
  try {
    answer = run(message);
  } catch (e) {
    // A trap (a panic, or memory exhausted): say so, and start afresh.
    instance = null;
    const why = panicked ? `the tracer panicked: ${panicked}` : `the tracer failed: ${e}`;
    answer = { ok: false, error: { text: why, problems: [] } };
  }
  answer.id = message.id;
  self.postMessage(answer, answer.rgba ? [answer.rgba] : []);
};
