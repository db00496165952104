//! Reading a glTF 2.0 file — `.gltf` JSON or `.glb` binary — and every buffer it names: the
//! GLB's binary chunk, `data:` URIs (base64) and files beside the `.gltf` (never the network).
//! The JSON is parsed by the `gltf` crate's types; indices are checked where they are followed
//! (not by the crate's validation, which panics on some bad indices), buffer lengths and
//! required extensions here. Every failure is a [`GltfError`] naming the
//! file and the glTF path, never a panic.

use std::fmt;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use ::gltf::json;
use base64::Engine;

/// Extensions the importer understands; any other in `extensionsRequired` is refused.
pub const SUPPORTED_EXTENSIONS: &[&str] = &["KHR_lights_punctual"];

/// A problem with a glTF file: the file, the glTF path inside it (`nodes[3].mesh`,
/// `accessors[5]`; empty for the file as a whole) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfError {
    pub file: String,
    pub path: String,
    pub message: String,
}

impl GltfError {
    pub fn new(file: &str, path: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            file: file.to_string(),
            path: path.into(),
            message: message.into(),
        }
    }

    /// The path and message without the file (`nodes[3].mesh: ...`).
    pub fn located_message(&self) -> String {
        if self.path.is_empty() {
            self.message.clone()
        } else {
            format!("{}: {}", self.path, self.message)
        }
    }
}

impl fmt::Display for GltfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file, self.located_message())
    }
}

impl std::error::Error for GltfError {}

/// A parsed glTF file with its buffers loaded, one byte vector per `buffers[i]`.
pub struct Document {
    /// The file's name in messages.
    pub file: String,
    pub root: json::Root,
    pub buffers: Vec<Vec<u8>>,
}

impl Document {
    pub fn error(&self, path: impl Into<String>, message: impl Into<String>) -> GltfError {
        GltfError::new(&self.file, path, message)
    }

    /// `items[index]`, of the top-level array named `what` (`"cameras"`), or an error at
    /// `what[index]` saying how many there are.
    pub fn item<'a, T>(
        &self,
        items: &'a [T],
        what: &str,
        index: usize,
    ) -> Result<&'a T, GltfError> {
        items.get(index).ok_or_else(|| {
            self.error(
                format!("{what}[{index}]"),
                format!("no such entry: the file has {} {what}", items.len()),
            )
        })
    }
}

/// Reads and parses a `.gltf` or `.glb` file; external buffers resolve against its folder.
pub fn read(path: &Path) -> Result<Document, GltfError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        let what = match e.kind() {
            std::io::ErrorKind::NotFound => "glTF file not found".to_string(),
            _ => format!("cannot read the glTF file: {e}"),
        };
        GltfError::new(&file, "", what)
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse(&bytes, &file, base)
}

/// Parses glTF bytes (JSON or GLB); `file` names it in messages, `base` is the folder external
/// buffer files are read from.
pub fn parse(bytes: &[u8], file: &str, base: &Path) -> Result<Document, GltfError> {
    // The crate's parsers are not ours to audit: contain a panic on hostile input as a refusal.
    let parsed = catch_unwind(AssertUnwindSafe(|| split_and_check(bytes, file)))
        .map_err(|_| GltfError::new(file, "", "the glTF parser failed on malformed input"))?;
    let (root, blob) = parsed?;
    for (i, ext) in root.extensions_required.iter().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(GltfError::new(
                file,
                format!("extensionsRequired[{i}]"),
                format!(
                    "extension {ext} is required by the file but not supported (supported: {})",
                    SUPPORTED_EXTENSIONS.join(", ")
                ),
            ));
        }
    }
    let mut blob = blob;
    let mut buffers = Vec::with_capacity(root.buffers.len());
    for (i, b) in root.buffers.iter().enumerate() {
        let path = format!("buffers[{i}]");
        let data = match &b.uri {
            None if i == 0 => blob.take().ok_or_else(|| {
                GltfError::new(
                    file,
                    &path,
                    "has no uri and the file has no GLB binary chunk",
                )
            })?,
            None => {
                return Err(GltfError::new(
                    file,
                    &path,
                    "has no uri (only buffers[0] may be a GLB's binary chunk)",
                ));
            }
            Some(uri) => load_uri(uri, base).map_err(|m| GltfError::new(file, &path, m))?,
        };
        let declared = b.byte_length.0;
        if (data.len() as u64) < declared {
            return Err(GltfError::new(
                file,
                format!("{path}.byteLength"),
                format!("is {declared} bytes but the buffer holds {}", data.len()),
            ));
        }
        buffers.push(data);
    }
    Ok(Document {
        file: file.to_string(),
        root,
        buffers,
    })
}

/// The JSON (a .glb's JSON chunk, or the whole file) deserialised — a type error names its
/// glTF path — and index-checked, with the .glb's binary chunk.
fn split_and_check(bytes: &[u8], file: &str) -> Result<(json::Root, Option<Vec<u8>>), GltfError> {
    let (text, blob) = if bytes.starts_with(b"glTF") {
        let glb = ::gltf::binary::Glb::from_slice(bytes)
            .map_err(|e| GltfError::new(file, "", format!("not a valid GLB file: {e}")))?;
        (glb.json.into_owned(), glb.bin.map(|b| b.into_owned()))
    } else {
        (bytes.to_vec(), None)
    };
    let de = &mut serde_json::Deserializer::from_slice(&text);
    let root: json::Root = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let path = if path == "." { String::new() } else { path };
        GltfError::new(
            file,
            path,
            format!("not valid glTF JSON: {}", e.into_inner()),
        )
    })?;
    // Not the crate's `validate`: it indexes arrays unchecked (a POSITION accessor index out
    // of range panics in gltf-json 1.4.1, found by tests/fuzz.rs). Every index this importer
    // follows is checked where it is followed, with its glTF path.
    Ok((root, blob))
}

/// A buffer's bytes from a `data:` URI or a file relative to `base`.
fn load_uri(uri: &str, base: &Path) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or("uri: a data: URI must be base64 (data:...;base64,...)")?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| format!("uri: invalid base64 in the data: URI: {e}"));
    }
    if uri.contains("://") {
        return Err(format!(
            "uri: {uri}: only files beside the glTF file and data: URIs are read (no network)"
        ));
    }
    let relative = percent_decode(uri).ok_or_else(|| format!("uri: {uri}: bad %-escape"))?;
    let full = base.join(relative);
    std::fs::read(&full).map_err(|e| format!("uri: cannot read {}: {e}", full.display()))
}

/// URI %-escapes (`%20`) decoded; None on a malformed escape or invalid UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_escapes_decode_and_bad_ones_are_refused() {
        assert_eq!(
            percent_decode("my%20level.bin").as_deref(),
            Some("my level.bin")
        );
        assert_eq!(percent_decode("a%2").as_deref(), None);
        assert_eq!(percent_decode("a%zz").as_deref(), None);
    }

    #[test]
    fn network_uris_and_missing_buffers_name_the_buffer() {
        let text =
            r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"http://x/y.bin","byteLength":4}]}"#;
        let e = parse(text.as_bytes(), "lvl.gltf", Path::new("."))
            .err()
            .unwrap();
        assert_eq!(e.path, "buffers[0]");
        assert!(e.message.contains("no network"), "{e}");
        let text = r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"data:application/octet-stream;base64,AAAA","byteLength":8}]}"#;
        let e = parse(text.as_bytes(), "lvl.gltf", Path::new("."))
            .err()
            .unwrap();
        assert_eq!(
            e.to_string(),
            "lvl.gltf: buffers[0].byteLength: is 8 bytes but the buffer holds 3"
        );
    }

    #[test]
    fn unsupported_required_extensions_are_refused() {
        let text = r#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"]}"#;
        let e = parse(text.as_bytes(), "lvl.gltf", Path::new("."))
            .err()
            .unwrap();
        assert_eq!(e.path, "extensionsRequired[0]", "{e}");
    }
}
