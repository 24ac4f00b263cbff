//! A material packed into a glTF binary (.glb) under our extension
//! [`EXTENSION`] (README, "Out to glTF"): the material directory's files, each in a buffer
//! view, listed on the glTF material:
//!
//! ```json
//! "extensions": { "EXT_brdfpaint_factored": {
//!     "version": 1,
//!     "files": [ { "name": "material.json", "bufferView": 4, "mimeType": "application/json" },
//!                { "name": "term0-factor0-light.exr", "bufferView": 5, "mimeType": "image/x-exr" } ] } }
//! ```
//!
//! The files are exactly those [`Material::save`] writes, so the packed material is whatever
//! version of the material format this build writes, and reads back through
//! [`Material::load`].

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::Material;
use crate::error::{Error, Result};

/// The extension's name, on the glTF material and in `extensionsUsed`.
pub const EXTENSION: &str = "EXT_brdfpaint_factored";
/// The extension's own version (its JSON layout, not the material format's).
pub const EXTENSION_VERSION: u64 = 1;
/// Largest .glb read for its packed material.
const MAX_GLB_BYTES: u64 = 1 << 30;

/// A file of a material directory: its name and bytes.
pub type File = (String, Vec<u8>);

/// A fresh directory under the system's temporary directory, removed on drop.
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Result<Scratch> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("brdfpaint-packed-{}-{n}", std::process::id()));
        std::fs::create_dir(&dir).map_err(|e| Error::Io { path: dir.clone(), source: e })?;
        Ok(Scratch(dir))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        // Our own directory, made by `new`: nothing of the user's is in it.
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The files of `material`'s directory (what [`Material::save`] writes, no hidden files).
pub fn pack(material: &Material) -> Result<Vec<File>> {
    let scratch = Scratch::new()?;
    let dir = scratch.0.join("material");
    material.save(&dir)?;
    let mut files = Vec::new();
    let entries = std::fs::read_dir(&dir).map_err(|e| Error::Io { path: dir.clone(), source: e })?;
    for entry in entries {
        let entry = entry.map_err(|e| Error::Io { path: dir.clone(), source: e })?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || !entry.path().is_file() {
            continue;
        }
        let bytes = std::fs::read(entry.path()).map_err(|e| Error::Io { path: entry.path(), source: e })?;
        files.push((name, bytes));
    }
    files.sort();
    Ok(files)
}

/// The material of packed `files` (names checked: plain file names only).
pub fn unpack(files: &[File], origin: &Path) -> Result<Material> {
    let scratch = Scratch::new()?;
    for (name, bytes) in files {
        let plain = !name.is_empty() && !name.starts_with('.') && !name.contains(['/', '\\']) && name.len() < 256;
        if !plain {
            return Err(Error::format(origin, format!("{EXTENSION}: file name {name:?} is not a plain file name")));
        }
        let path = scratch.0.join(name);
        std::fs::write(&path, bytes).map_err(|e| Error::Io { path, source: e })?;
    }
    Material::load(&scratch.0.join("material.json")).map_err(|e| Error::format(origin, format!("its {EXTENSION} material: {e}")))
}

/// Whether `path` names a glTF binary.
pub fn is_glb(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("glb"))
}

/// The exact material a .glb written by `brdfpaint export --gltf` carries.
pub fn load_glb(path: &Path) -> Result<Material> {
    let bytes = crate::fsio::read_regular(path, MAX_GLB_BYTES)?;
    let (json, bin) = split_glb(&bytes).map_err(|e| Error::format(path, e))?;
    let files = packed_files(&json, bin).map_err(|e| Error::format(path, e))?;
    unpack(&files, path)
}

/// A GLB's JSON and BIN chunks.
pub fn split_glb(bytes: &[u8]) -> std::result::Result<(Value, &[u8]), String> {
    let word = |at: usize| -> Option<u32> { bytes.get(at..at + 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])) };
    if word(0) != Some(0x4654_6C67) || word(4) != Some(2) {
        return Err("not a glTF 2.0 binary (.glb)".into());
    }
    let mut at = 12;
    let (mut json, mut bin) = (None, &bytes[0..0]);
    while let (Some(len), Some(kind)) = (word(at), word(at + 4)) {
        let body = bytes.get(at + 8..at + 8 + len as usize).ok_or("a chunk runs past the end of the file")?;
        match kind {
            0x4E4F_534A => json = Some(serde_json::from_slice::<Value>(body).map_err(|e| format!("its JSON: {e}"))?),
            0x004E_4942 => bin = body,
            _ => {}
        }
        at += 8 + len as usize;
    }
    Ok((json.ok_or("no JSON chunk")?, bin))
}

/// The files listed by the first material carrying [`EXTENSION`].
fn packed_files(json: &Value, bin: &[u8]) -> std::result::Result<Vec<File>, String> {
    let ext = json["materials"]
        .as_array()
        .and_then(|ms| ms.iter().find_map(|m| m["extensions"].get(EXTENSION)))
        .ok_or_else(|| format!("no {EXTENSION} material: not a glTF material brdfpaint exported"))?;
    let version = ext["version"].as_u64();
    if version != Some(EXTENSION_VERSION) {
        return Err(format!("{EXTENSION} version {version:?}; this brdfpaint reads version {EXTENSION_VERSION}"));
    }
    let views = json["bufferViews"].as_array().ok_or("no bufferViews")?;
    let mut files = Vec::new();
    for f in ext["files"].as_array().ok_or("no files in the extension")? {
        let name = f["name"].as_str().ok_or("a packed file without a name")?;
        let view = f["bufferView"].as_u64().and_then(|k| views.get(k as usize)).ok_or_else(|| format!("{name}: no bufferView"))?;
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = view["byteLength"].as_u64().ok_or_else(|| format!("{name}: no byteLength"))? as usize;
        let body = bin.get(offset..offset.saturating_add(len)).ok_or_else(|| format!("{name}: outside the binary chunk"))?;
        files.push((name.to_string(), body.to_vec()));
    }
    Ok(files)
}
