//! The binary container (`.glb`): a 12-byte header, a JSON chunk, and an
//! optional BIN chunk that buffer 0 reads when it has no `uri`.

use super::Failure;

const MAGIC: &[u8; 4] = b"glTF";
const JSON: u32 = 0x4E4F_534A;
const BIN: u32 = 0x004E_4942;

/// A .glb file's JSON text and BIN chunk.
pub(crate) struct Glb<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

/// Splits a .glb file into its chunks, every length checked against the
/// bytes there are.
pub(crate) fn split(bytes: &[u8]) -> Result<Glb<'_>, Failure> {
    let bad = |m: String| Failure::file(m);
    if bytes.len() < 12 {
        return Err(bad(format!(
            "the file is {} bytes; a .glb file starts with a 12-byte header",
            bytes.len()
        )));
    }
    if &bytes[..4] != MAGIC {
        return Err(bad(format!(
            "expected a .glb file starting with the magic `glTF`, found {:?}; a text glTF file is named .gltf",
            String::from_utf8_lossy(&bytes[..4])
        )));
    }
    let version = u32_at(bytes, 4);
    if version != 2 {
        return Err(bad(format!(
            "expected a .glb file of version 2, found version {version}"
        )));
    }
    let length = u32_at(bytes, 8) as usize;
    if length > bytes.len() {
        return Err(bad(format!(
            "the header says the file is {length} bytes, but it is {}: the file is truncated",
            bytes.len()
        )));
    }
    let mut chunks = Vec::new();
    let mut at = 12;
    while at < length {
        if length - at < 8 {
            return Err(bad(format!(
                "a chunk header at byte {at} is cut short by the end of the file"
            )));
        }
        let size = u32_at(bytes, at) as usize;
        let kind = u32_at(bytes, at + 4);
        let start = at + 8;
        if size > length - start {
            return Err(bad(format!(
                "the chunk at byte {at} says it holds {size} bytes, but only {} follow: the file is truncated",
                length - start
            )));
        }
        chunks.push((kind, &bytes[start..start + size]));
        at = start + size;
    }
    match chunks.as_slice() {
        [(JSON, json), rest @ ..] => Ok(Glb {
            json,
            bin: rest.first().filter(|(k, _)| *k == BIN).map(|(_, b)| *b),
        }),
        _ => Err(bad(
            "expected the first chunk of a .glb file to be its JSON".to_string(),
        )),
    }
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// A .glb file of `json` and `bin` (tests, and `tracer pack`'s checks).
pub fn assemble(json: &str, bin: Option<&[u8]>) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let mut json = json.as_bytes().to_vec();
    json.extend(std::iter::repeat_n(b' ', pad(json.len())));
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&JSON.to_le_bytes());
    out.extend_from_slice(&json);
    if let Some(bin) = bin {
        let mut bin = bin.to_vec();
        bin.extend(std::iter::repeat_n(0, pad(bin.len())));
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&BIN.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    let total = out.len() as u32;
    out[8..12].copy_from_slice(&total.to_le_bytes());
    out
}
