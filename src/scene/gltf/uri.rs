//! Where a glTF file's bytes come from: `data:` URIs (base64 or percent-encoded), files next
//! to the model (regular files only, never outside its folder, a buffer read no further than
//! its declared length) and the GLB binary chunk; see the limits in the parent module's docs.

use super::*;

/// Decodes a `data:` URI's payload (base64 or percent-encoded).
fn decode_data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let (header, payload) = uri
        .strip_prefix("data:")
        .and_then(|rest| rest.split_once(','))
        .ok_or("a data: URI without a comma")?;
    if header.ends_with(";base64") {
        base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| format!("bad base64 in its data: URI ({e})"))
    } else {
        Ok(percent_decode(payload))
    }
}

/// Percent-decodes a URI (`%20` to a space); malformed escapes are kept as written.
fn percent_decode(uri: &str) -> Vec<u8> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(value)) => {
                out.push(value);
                i += 3;
            }
            (byte, _) => {
                out.push(byte);
                i += 1;
            }
        }
    }
    out
}

/// What a URI is read as: a buffer (no further than its declared length) or an image.
#[derive(Clone, Copy)]
pub(super) enum UriUse {
    Buffer { length: u64 },
    Image,
}

/// Whether a relative path leaves the folder it is relative to (absolute, or `..` climbing
/// above it).
fn leaves_folder(relative: &Path) -> bool {
    let mut depth = 0usize;
    for component in relative.components() {
        match component {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth == 0 => return true,
            Component::ParentDir => depth -= 1,
            Component::RootDir | Component::Prefix(_) => return true,
        }
    }
    false
}

/// Reads a URI a glTF file names: a `data:` URI or a path relative to the file, inside its
/// folder, read within the bounds of its use (see the module docs).
pub(super) fn read_uri(base: &Path, uri: &str, usage: UriUse) -> Result<(Vec<u8>, String), String> {
    if uri.starts_with("data:") {
        return decode_data_uri(uri).map(|bytes| (bytes, "an embedded data: URI".to_owned()));
    }
    if let Some((scheme, _)) = uri.split_once("://") {
        return Err(format!(
            "{uri} is a {scheme}:// URI; only files and data: URIs are read"
        ));
    }
    let decoded = String::from_utf8_lossy(&percent_decode(uri)).into_owned();
    if leaves_folder(Path::new(&decoded)) {
        return Err(format!(
            "{uri} lies outside the model's folder; aa-lab reads only files in the folder of \
             the glTF file and below it"
        ));
    }
    let path = base.join(decoded);
    let bytes = match usage {
        UriUse::Buffer { length } => files::read_head(&path, length, "a glTF buffer"),
        UriUse::Image => files::read_bounded(&path, MAX_IMAGE_FILE_BYTES, "a texture"),
    }
    .map_err(|e| e.to_string())?;
    Ok((bytes, path.display().to_string()))
}

/// Every buffer's bytes, checked against its declared length.
pub(super) fn load_buffers(
    path: &Path,
    base: &Path,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, GltfError> {
    let invalid = |message: String| GltfError::Invalid {
        path: path.to_owned(),
        message,
    };
    document
        .buffers()
        .map(|buffer| {
            let name = describe("buffer", buffer.index(), buffer.name());
            let length = buffer.length() as u64;
            if length > MAX_BUFFER_BYTES {
                return Err(invalid(format!(
                    "{name} declares {length} bytes, more than the {MAX_BUFFER_BYTES} bytes \
                     aa-lab reads for a glTF buffer"
                )));
            }
            let (data, from) = match buffer.source() {
                gltf::buffer::Source::Bin => (
                    blob.take().ok_or_else(|| {
                        invalid(format!(
                            "{name} refers to the GLB binary chunk, but the file has none"
                        ))
                    })?,
                    "the GLB binary chunk".to_owned(),
                ),
                gltf::buffer::Source::Uri(uri) => read_uri(base, uri, UriUse::Buffer { length })
                    .map_err(|e| invalid(format!("{name}: {e}")))?,
            };
            if data.len() < buffer.length() {
                return Err(invalid(format!(
                    "{name} declares {} bytes, but {from} holds only {}",
                    buffer.length(),
                    data.len()
                )));
            }
            Ok(data)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uris_decode() {
        assert_eq!(
            decode_data_uri("data:application/octet-stream;base64,AAEC").as_deref(),
            Ok(&[0u8, 1, 2][..])
        );
        assert_eq!(decode_data_uri("data:,a%20b").as_deref(), Ok(&b"a b"[..]));
        assert!(decode_data_uri("data:;base64,@@@").is_err());
        assert!(decode_data_uri("data:nocomma").is_err());
    }

    #[test]
    fn uris_outside_the_folder_are_recognised() {
        assert!(!leaves_folder(Path::new("a.bin")));
        assert!(!leaves_folder(Path::new("./textures/../a.png")));
        assert!(leaves_folder(Path::new("../a.png")));
        assert!(leaves_folder(Path::new("textures/../../a.png")));
        assert!(leaves_folder(Path::new("/dev/zero")));
    }
}
