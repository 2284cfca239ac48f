//! A glTF file's buffers: a .glb's BIN chunk, a data URI (base64) or a
//! file beside the glTF, each checked to hold the `byteLength` it claims.

use super::doc::Document;
use super::Failure;
use crate::key_path::KeyPath;
use crate::source::Source;
use std::path::{Path, PathBuf};

/// Most bytes a glTF file's buffers (and its images' files) may hold
/// together: what an OBJ file may be.
pub const MAX_BUFFER_BYTES: u64 = crate::read::MAX_OBJ_BYTES;

/// Every buffer's bytes, in the file's order, and the external files read.
pub(crate) fn load(
    doc: &Document,
    bin: Option<&[u8]>,
    base: &Path,
    source: &dyn Source,
) -> Result<(Vec<Vec<u8>>, Vec<PathBuf>), Failure> {
    let total: u64 = doc
        .buffers
        .iter()
        .fold(0u64, |sum, b| sum.saturating_add(b.byte_length));
    if total > MAX_BUFFER_BYTES {
        return Err(Failure::at(
            KeyPath::root().key("buffers"),
            format!(
                "the buffers claim {total} bytes together; expected at most {MAX_BUFFER_BYTES}"
            ),
        ));
    }
    let mut buffers = Vec::with_capacity(doc.buffers.len());
    let mut files = Vec::new();
    for (i, buffer) in doc.buffers.iter().enumerate() {
        let path = KeyPath::root().key("buffers").index(i);
        let bytes = match &buffer.uri {
            None if i == 0 && bin.is_some() => bin.expect("checked").to_vec(),
            None => {
                return Err(Failure::at(
                    path.key("uri"),
                    "expected a `uri` (a .bin file or a data URI): only buffer 0 of a .glb file may leave it out, to read the file's BIN chunk".to_string(),
                ))
            }
            Some(uri) => {
                let (bytes, file) = read_uri(uri, base, source, buffer.byte_length)
                    .map_err(|m| Failure::at(path.key("uri"), m))?;
                files.extend(file);
                bytes
            }
        };
        if (bytes.len() as u64) < buffer.byte_length {
            return Err(Failure::at(
                path.key("byteLength"),
                format!(
                    "the buffer claims {} bytes but holds {}: expected at least `byteLength` bytes",
                    buffer.byte_length,
                    bytes.len()
                ),
            ));
        }
        buffers.push(bytes);
    }
    Ok((buffers, files))
}

/// The bytes a `uri` names: a data URI's, or a file's relative to `base`
/// (read up to `cap` bytes beyond which it could not be what it claims,
/// plus the padding a writer may add), and that file.
pub(crate) fn read_uri(
    uri: &str,
    base: &Path,
    source: &dyn Source,
    cap: u64,
) -> Result<(Vec<u8>, Option<PathBuf>), String> {
    if let Some(data) = uri.strip_prefix("data:") {
        let Some((_, payload)) = data.split_once(";base64,") else {
            return Err(
                "expected a base64 data URI (`data:...;base64,...`); other data URIs are not read"
                    .to_string(),
            );
        };
        return decode_base64(payload).map(|bytes| (bytes, None));
    }
    let name = percent_decoded(uri)?;
    if name.contains("://") {
        return Err(format!(
            "cannot read `{uri}`: only files beside the glTF file and data URIs are read, nothing from the network"
        ));
    }
    let path = base.join(&name);
    let bytes = source
        .read(&path, cap.saturating_add(3).min(MAX_BUFFER_BYTES))
        .map_err(|e| format!("cannot read `{name}`: {e}"))?;
    Ok((bytes, Some(path)))
}

/// A relative URI's `%XX` escapes decoded (glTF writers escape spaces).
pub(crate) fn percent_decoded(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = uri.get(i + 1..i + 3);
            let value = hex.and_then(|h| u8::from_str_radix(h, 16).ok());
            let Some(value) = value else {
                return Err(format!(
                    "expected `%` followed by two hexadecimal digits in the URI `{uri}`"
                ));
            };
            out.push(value);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("the URI `{uri}` does not decode to UTF-8 text"))
}

/// Standard base64 (RFC 4648, `+` and `/`, `=` padding optional), or
/// where it is not.
pub(crate) fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
    use base64::{alphabet, DecodeError, Engine};
    // Lenient as glTF writers need: padding left out or not (trimmed
    // first, so none is left), the last character's unused bits not checked.
    const LENIENT: GeneralPurpose = GeneralPurpose::new(
        &alphabet::STANDARD,
        GeneralPurposeConfig::new()
            .with_decode_padding_mode(DecodePaddingMode::RequireNone)
            .with_decode_allow_trailing_bits(true),
    );
    LENIENT
        .decode(text.trim_end_matches('='))
        .map_err(|e| match e {
            DecodeError::InvalidByte(at, c) => format!(
                "the data URI is not base64: character {} of its data is {:?}; expected A-Z, a-z, 0-9, + or /",
                at + 1,
                char::from(c)
            ),
            DecodeError::InvalidLength(_) => {
                "the data URI is not base64: its length leaves a lone character".to_string()
            }
            other => format!("the data URI is not base64: {other}"),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_as_the_standard_says() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("Zg==").unwrap(), b"f");
        assert_eq!(decode_base64("Zm8=").unwrap(), b"fo");
        assert_eq!(decode_base64("Zm9v").unwrap(), b"foo");
        assert_eq!(decode_base64("Zm9vYmFy").unwrap(), b"foobar");
        assert_eq!(decode_base64("AACAPw").unwrap(), 1f32.to_le_bytes());
        let err = decode_base64("Zm9v!").unwrap_err();
        assert!(err.contains("character 5"), "{err}");
        let err = decode_base64("Zm9vY").unwrap_err();
        assert!(err.contains("lone character"), "{err}");
    }

    #[test]
    fn escaped_names_are_decoded() {
        assert_eq!(percent_decoded("my%20model.bin").unwrap(), "my model.bin");
        assert!(percent_decoded("a%2").is_err());
    }
}
