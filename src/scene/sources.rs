//! What a glTF file may read, and what must be checked before the gltf crate sees it: the
//! file-access policy for buffers and images (README, "File access": regular files inside
//! the scene's directory, with a size cap), data: URIs, and what gltf's validation would
//! index without checking.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Rejects files that are plainly not glTF by their extension, with a message that says what
/// is read instead.
pub(super) fn check_extension(path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("gltf" | "glb") => Ok(()),
        Some(other) => Err(Error::format(
            path,
            format!("unsupported format .{other}: models and scenes are read from glTF 2.0 (.gltf or .glb); convert it, e.g. with Blender"),
        )),
        None => Err(Error::format(path, "unsupported format: expected a glTF 2.0 file (.gltf or .glb)")),
    }
}

/// What gltf's validation would index without checking, or what gltf's accessors would
/// unwrap: a POSITION accessor index out of range, an image with neither a uri nor a
/// bufferView, an image in a bufferView without a mimeType.
pub(super) fn check_before_validation(json: &gltf::json::Root) -> std::result::Result<(), String> {
    use gltf::json::validation::Checked;
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&Checked::Valid(gltf::Semantic::Positions)) {
                if index.value() >= json.accessors.len() {
                    return Err(format!(
                        "mesh {m} primitive {p}: POSITION names accessor {} of {}",
                        index.value(),
                        json.accessors.len()
                    ));
                }
            }
        }
    }
    for (i, image) in json.images.iter().enumerate() {
        match (&image.uri, &image.buffer_view) {
            (None, None) => return Err(format!("image {i} has neither a uri nor a bufferView")),
            (Some(_), Some(_)) => return Err(format!("image {i} has both a uri and a bufferView")),
            (None, Some(_)) if image.mime_type.is_none() => {
                return Err(format!("image {i} is stored in a bufferView but has no mimeType"))
            }
            _ => {}
        }
    }
    Ok(())
}

/// Every image file the document names must be a readable file inside `base` (it is not
/// decoded: textures play no part here); the error names the file.
pub(super) fn check_images(path: &Path, base: Option<&Path>, document: &gltf::Document) -> Result<()> {
    for (i, image) in document.as_json().images.iter().enumerate() {
        let Some(uri) = image.uri.as_deref() else { continue };
        if uri.starts_with("data:") {
            continue;
        }
        let file = external_file(path, base, "texture", uri)?;
        crate::fsio::check_regular(&file, u64::MAX).map_err(|e| Error::format(path, format!("image {i}: {e}")))?;
    }
    Ok(())
}

/// The file a uri names, under the file-access policy: a local file inside `base` (README,
/// "File access"). `what` is "buffer" or "texture".
pub(super) fn external_file(path: &Path, base: Option<&Path>, what: &str, uri: &str) -> Result<PathBuf> {
    if uri.contains("://") {
        return Err(Error::format(path, format!("{what} {uri}: only local files and data: URIs are supported")));
    }
    let Some(base) = base else {
        return Err(Error::format(path, format!("{what} {uri}: external files are not supported here")));
    };
    crate::fsio::resolve_inside(base, &percent_decode(uri)).map_err(|refused| match refused {
        crate::fsio::Refused::Missing(file, e) => {
            Error::format(path, format!("missing {what} file {}: {e}", file.display()))
        }
        crate::fsio::Refused::Outside(reason) => Error::format(path, format!("{what} {uri}: {reason}")),
    })
}

/// The data of every buffer: the GLB binary chunk, a data: URI, or a file read under the
/// file-access policy (regular, inside `base`, at most [`crate::fsio::MAX_SCENE_BYTES`]).
/// Each is checked to hold the bytes it declares and padded to a multiple of 4, as gltf's
/// reader expects.
pub(super) fn read_buffers(
    path: &Path,
    base: Option<&Path>,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<gltf::buffer::Data>> {
    let mut out = Vec::new();
    for buffer in document.buffers() {
        let i = buffer.index();
        let what = format!("buffer {i}");
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| Error::format(path, format!("{what} has no uri and there is no GLB binary chunk for it")))?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                decode_data_uri(uri).map_err(|reason| Error::format(path, format!("{what}: {reason}")))?
            }
            gltf::buffer::Source::Uri(uri) => {
                let file = external_file(path, base, "buffer", uri)?;
                crate::fsio::read_regular(&file, crate::fsio::MAX_SCENE_BYTES)
                    .map_err(|e| Error::format(path, format!("{what}: {e}")))?
            }
        };
        if data.len() < buffer.length() {
            return Err(Error::format(
                path,
                format!("{what} holds {} bytes of the {} it declares (truncated?)", data.len(), buffer.length()),
            ));
        }
        while data.len() % 4 != 0 {
            data.push(0);
        }
        out.push(gltf::buffer::Data(data));
    }
    Ok(out)
}

/// The bytes of a `data:[<type>][;base64],<data>` URI.
pub(super) fn decode_data_uri(uri: &str) -> std::result::Result<Vec<u8>, String> {
    let (header, data) = uri.split_once(',').ok_or("a data: URI without a comma")?;
    if header.ends_with(";base64") {
        base64::decode(data).map_err(|e| format!("invalid base64 in its data: URI ({e})"))
    } else {
        Ok(percent_decode(data).into_bytes())
    }
}

/// Decodes %XX escapes of a relative URI (glTF URIs are percent-encoded).
pub(super) fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            if let Some(v) = uri.get(i + 1..i + 3).and_then(|h| u8::from_str_radix(h, 16).ok()) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b.bin"), "a b.bin");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz%41"), "%zzA");
    }
}
