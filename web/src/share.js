// Share links: the scene's text, deflated (the browser's CompressionStream)
// and base64url-encoded, in the URL's fragment, which no server sees.

async function pipe(bytes, stream) {
  const out = new Blob([bytes]).stream().pipeThrough(stream);
  return new Uint8Array(await new Response(out).arrayBuffer());
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

// `{name, text}` of a fragment made by `encodeShare`, or null.
export async function decodeShare(fragment) {
  const params = new URLSearchParams(fragment);
  const packed = params.get("text");
  if (!packed) return null;
  try {
    const bytes = await pipe(fromBase64url(packed), new DecompressionStream("deflate-raw"));
    return { name: params.get("scene") || "shared.toml", text: new TextDecoder().decode(bytes) };
  } catch {
    return null;
  }
}
