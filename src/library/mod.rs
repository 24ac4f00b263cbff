//! A MatCap library in one command: `fit --lit-sphere A.png B.jpg DIR/ … --out LIB`.
//!
//! ```text
//! files and folders ──gather──► pictures (a folder: its PNG, JPEG and EXR files, sorted)
//! pictures ──names──► LIB/NAME/ per picture (the file's stem; stem-ext where stems collide)
//! each picture ──litsphere::fit, LitSphere::save──► LIB/NAME/ (as `fit --lit-sphere P --out LIB/NAME`)
//! materials ──gallery──► LIB/gallery.png, LIB/rows/NAME.png ──index──► LIB/index.html
//! ```
//!
//! The library is staged beside LIB and committed in one step ([`crate::commit::StagedDir`]):
//! it appears whole or not at all, and on a rerun only the files the tool wrote there are
//! replaced or removed; the user's files, in LIB and in its material folders, stay.

mod build;
pub mod gallery;
mod index;

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::factor::Errors;

pub use build::{build, Failed, Fitted, Job, Outcome, Report};

/// The extensions a folder's pictures have (any case).
pub const EXTENSIONS: [&str; 4] = ["png", "jpg", "jpeg", "exr"];
/// The library's own files at its top; a material folder never takes these names.
pub const GALLERY: &str = "gallery.png";
pub const INDEX: &str = "index.html";
pub const MANIFEST: &str = "library.json";
/// The folder of each material's gallery row, `rows/NAME.png`.
pub const ROWS: &str = "rows";
/// [`MANIFEST`]'s format tag.
const FORMAT: &str = "brdfpaint-library";
const VERSION: u32 = 1;

/// A picture to fit and the name of its material folder.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    pub path: PathBuf,
    pub name: String,
}

/// The pictures named on the command line, in order, and what each folder held.
#[derive(Debug, Default)]
pub struct Inputs {
    pub pictures: Vec<Picture>,
    /// Per folder given: the folder, its pictures and its other entries (ignored).
    pub folders: Vec<(PathBuf, usize, usize)>,
}

impl Inputs {
    /// Whether these inputs make a library rather than one material: several pictures, or a
    /// folder.
    pub fn is_library(&self) -> bool {
        self.pictures.len() > 1 || !self.folders.is_empty()
    }
}

/// The pictures of `args`: a file is itself, a folder every PNG, JPEG and EXR file in it
/// (not in its subfolders; hidden files skipped), sorted by name. A picture named twice is
/// fitted once. Errors, one line: a path that is missing, a folder without pictures.
pub fn gather(args: &[PathBuf]) -> Result<Inputs> {
    let mut inputs = Inputs::default();
    let mut paths = Vec::new();
    for arg in args {
        let meta = std::fs::metadata(arg).map_err(|e| Error::io(arg, e))?;
        if !meta.is_dir() {
            paths.push(arg.clone());
            continue;
        }
        let (found, others) = folder_pictures(arg)?;
        if found.is_empty() {
            return Err(Error::input(format!("{}: no PNG, JPEG or EXR picture in this folder", arg.display())));
        }
        inputs.folders.push((arg.clone(), found.len(), others));
        paths.extend(found);
    }
    let mut seen = std::collections::HashSet::new();
    paths.retain(|p| seen.insert(p.canonicalize().unwrap_or_else(|_| p.clone())));
    let names = names(&paths);
    inputs.pictures = paths.into_iter().zip(names).map(|(path, name)| Picture { path, name }).collect();
    Ok(inputs)
}

/// A folder's pictures, sorted, and how many other entries it has.
fn folder_pictures(dir: &Path) -> Result<(Vec<PathBuf>, usize)> {
    let mut found = Vec::new();
    let mut others = 0;
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let path = entry.path();
        let hidden = entry.file_name().to_string_lossy().starts_with('.');
        let file = std::fs::metadata(&path).is_ok_and(|m| m.is_file());
        if file && !hidden && is_picture(&path) {
            found.push(path);
        } else {
            others += 1;
        }
    }
    found.sort();
    Ok((found, others))
}

/// Whether `path` has a picture's extension.
fn is_picture(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
}

/// The material folder names of `paths`, distinct ignoring case (so they stay distinct on
/// every file system): the file's stem (`a.png` → `a`, leading dots dropped); where two
/// pictures share a stem, or a stem is one of the library's own files, each of them becomes
/// stem-ext (`a.png`, `a.jpg` → `a-png`, `a-jpg`); where that still collides (the same file
/// name in two folders), the second and later get `-2`, `-3`, … in the order given.
pub fn names(paths: &[PathBuf]) -> Vec<String> {
    let stem = |p: &PathBuf| {
        let s = p.file_stem().map(|s| s.to_string_lossy().trim_start_matches('.').to_string()).unwrap_or_default();
        if s.is_empty() { "picture".to_string() } else { s }
    };
    let ext = |p: &PathBuf| p.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    let stems: Vec<String> = paths.iter().map(stem).collect();
    let count = |s: &str| stems.iter().filter(|t| t.to_lowercase() == s.to_lowercase()).count();
    let mut taken = std::collections::HashSet::new();
    let mut out = Vec::new();
    for (p, s) in paths.iter().zip(&stems) {
        let reserved = [GALLERY, INDEX, MANIFEST, ROWS].iter().any(|r| r.eq_ignore_ascii_case(s));
        let base = if count(s) > 1 || reserved { format!("{s}-{}", ext(p)) } else { s.clone() };
        let mut name = base.clone();
        let mut k = 2;
        while !taken.insert(name.to_lowercase()) {
            name = format!("{base}-{k}");
            k += 1;
        }
        out.push(name);
    }
    out
}

/// One material of a library, as [`MANIFEST`] lists it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Entry {
    /// The material folder, `LIB/NAME`.
    pub name: String,
    /// The picture it was fitted to, as given.
    pub picture: String,
    /// The key light it was fitted with, towards the light (x right, y up, z to the viewer).
    pub light: [f64; 3],
    pub errors: Errors,
}

/// `LIB/library.json`: the library's materials, in the order of its gallery.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Manifest {
    pub format: String,
    pub version: u32,
    pub materials: Vec<Entry>,
}

impl Manifest {
    pub fn new(materials: Vec<Entry>) -> Manifest {
        Manifest { format: FORMAT.into(), version: VERSION, materials }
    }

    /// The manifest of the library at `dir`. Errors, one line: none there, or not ours.
    pub fn read(dir: &Path) -> Result<Manifest> {
        let path = dir.join(MANIFEST);
        let bytes = crate::fsio::read_regular(&path, 16 << 20)?;
        let m: Manifest = serde_json::from_slice(&bytes).map_err(|e| Error::format(&path, e.to_string()))?;
        if m.format != FORMAT || m.version != VERSION {
            return Err(Error::format(&path, format!("not a {FORMAT} {VERSION} manifest")));
        }
        Ok(m)
    }

    fn write(&self, dir: &Path) -> Result<()> {
        let path = dir.join(MANIFEST);
        let text = serde_json::to_string_pretty(self).map_err(|e| Error::format(&path, e.to_string()))?;
        crate::commit::write_atomic(&path, text.as_bytes())
    }
}

impl Entry {
    fn new(name: &str, picture: &Path, light: DVec3, errors: Errors) -> Entry {
        Entry { name: name.into(), picture: picture.display().to_string(), light: light.to_array(), errors }
    }
}

/// Whether a library may be written to `dir`: nothing there, an empty folder, or an earlier
/// library (its [`MANIFEST`] reads). Anything else is refused with one line, before any work.
pub fn check_output(dir: &Path) -> Result<()> {
    if crate::commit::output_dir_is_fresh(dir)? || Manifest::read(dir).is_ok() {
        return Ok(());
    }
    Err(Error::input(format!(
        "{} exists and is not a library (no {MANIFEST} written by brdfpaint); not overwriting it: give a new or empty folder",
        dir.display()
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(names: &[&str]) -> Vec<PathBuf> {
        names.iter().map(PathBuf::from).collect()
    }

    #[test]
    fn names_are_stems_and_stem_ext_only_where_stems_collide() {
        assert_eq!(names(&p(&["m/a.png", "m/b.exr"])), ["a", "b"]);
        assert_eq!(names(&p(&["m/a.png", "m/A.JPG", "m/b.exr"])), ["a-png", "A-jpg", "b"]);
        assert_eq!(names(&p(&["x/a.png", "y/a.png"])), ["a-png", "a-png-2"]);
        assert_eq!(names(&p(&["m/gallery.png.png", "m/.hidden.png", "m/.png"])), ["gallery.png-png", "hidden", "png"]);
    }
}
