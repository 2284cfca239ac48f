// Share links: the scene's text, deflated (the browser's CompressionStream)
// and base64url-encoded, in the URL's fragment, which no server sees.

// The most a link's scene may inflate to: the page's own limit of a scene
// file (scene-format's MAX_SCENE_BYTES, which the page's loader holds every
// scene file to). A link of 2 MB could otherwise inflate to gigabytes in
// the tab before anything looked at it.
export const MAX_SCENE_BYTES = 64 * 1024 * 1024;

async function pipe(bytes, stream) {
  const out = new Blob([bytes]).stream().pipeThrough(stream);
  return new Uint8Array(await new Response(out).arrayBuffer());
}

// The bytes `packed` inflates to, read a chunk at a time; null as soon as
// they pass `cap` (the rest is never made).
async function inflate(packed, cap) {
  const reader = new Blob([packed]).stream().pipeThrough(new DecompressionStream("deflate-raw")).getReader();
  const chunks = [];
  let total = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    total += value.length;
    if (total > cap) {
      await reader.cancel();
      return null;
    }
    chunks.push(value);
  }
  const bytes = new Uint8Array(total);
  let at = 0;
  for (const chunk of chunks) {
    bytes.set(chunk, at);
    at += chunk.length;
  }
  return bytes;
}

function toBase64url(bytes) {
  let s = "";
  for (const b of bytes) s += String.fromCharCode(b);
  return btoa(s).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

function fromBase64url(text) {
  const s = atob(text.replace(/-/g, "+").replace(/_/g, "/"));
  return Uint8Array.from(s, (c) => c.charCodeAt(0));
}

// The fragment for scene `name` holding `text`.
export async function encodeShare(name, text) {
  const packed = await pipe(new TextEncoder().encode(text), new CompressionStream("deflate-raw"));
  return `scene=${encodeURIComponent(name)}&text=${toBase64url(packed)}`;
}

// `{name, text}` of a fragment made by `encodeShare`; `{refused}` (why, in
// words) for one whose scene would pass the page's limit; null for one
// that cannot be read (cut short).
export async function decodeShare(fragment) {
  const params = new URLSearchParams(fragment);
  const packed = params.get("text");
  if (!packed) return null;
  try {
    const bytes = await inflate(fromBase64url(packed), MAX_SCENE_BYTES);
    if (!bytes) {
      const mib = MAX_SCENE_BYTES / (1024 * 1024);
      return { refused: `its scene is over ${mib} MiB once inflated, more than the page reads of a scene file` };
    }
    return { name: params.get("scene") || "shared.toml", text: new TextDecoder().decode(bytes) };
  } catch {
    return null;
  }
}
