//! Which files of an output folder the tool wrote (README, "File access and outputs").
//!
//! A folder the tool writes whole (a material, a sheet, a demo) or writes a sequence into
//! holds a record, [`RECORD`]: each file the tool wrote there, by its path relative to the
//! folder and the SHA-256 of its content, sealed ([`super::seal`]). A later run may replace
//! or remove a file only if the record is intact and names that path with the content the
//! file has now. Everything else is the user's: a file added, edited or renamed, a folder, a
//! link, a name the record does not hold, and every file where the record is missing, forged
//! or copied from elsewhere (then only an output's own fixed rule applies: [`Legacy`]).

use std::collections::{BTreeMap, BTreeSet};
use std::io::Read;
use std::path::Path;

use sha2::{Digest, Sha256};

use super::seal;
use crate::error::{Error, Result};

/// The record's file name, in the folder it describes.
pub const RECORD: &str = ".brdfpaint-owned";
/// The record's first line: its format and version.
const HEADER: &str = "brdfpaint-owned 1";
/// Largest record read: a demo records a few hundred files, a long turntable thousands.
const MAX_RECORD_BYTES: u64 = 8 << 20;

/// What a folder without a valid record lets a run replace (regular files only): the names
/// a version without records wrote there.
#[derive(Clone, Debug)]
pub enum Legacy {
    /// These relative paths.
    Paths(BTreeSet<String>),
    /// The paths the new output writes again.
    Rewritten,
}

/// Which files of an existing output folder a new output may replace or remove.
#[derive(Clone, Debug)]
pub struct Claim {
    /// The files that define the output, replaced whatever their content (a material's
    /// material.json: README, "File access and outputs").
    pub fixed: BTreeSet<String>,
    /// Where the folder has no valid record, what else it may replace.
    pub legacy: Legacy,
}

impl Claim {
    pub fn new(fixed: &[&str], legacy: Legacy) -> Claim {
        Claim { fixed: fixed.iter().map(|s| s.to_string()).collect(), legacy }
    }
}

/// The files the tool wrote in one folder, by relative path (`/`-separated), with the
/// SHA-256 of their content.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Record {
    files: BTreeMap<String, [u8; 32]>,
}

impl Record {
    /// The sealed record of `dir`; `None` when there is none, or it is not whole, not
    /// sealed by this user's key, or not a regular file.
    pub fn read(dir: &Path) -> Option<Record> {
        let bytes = crate::fsio::read_regular(&dir.join(RECORD), MAX_RECORD_BYTES).ok()?;
        let text = String::from_utf8(bytes).ok()?;
        let mut lines = seal::open(&text)?.lines();
        (lines.next()? == HEADER).then_some(())?;
        let mut files = BTreeMap::new();
        for line in lines {
            let (hash, path) = line.split_once(' ')?;
            files.insert(path.to_string(), unhex(hash)?);
        }
        Some(Record { files })
    }

    /// The record of every regular file under `dir` (what a run just staged there), the
    /// record's own file at the top excepted.
    pub fn of_tree(dir: &Path) -> Result<Record> {
        let mut record = Record::default();
        record.add_tree(dir, "")?;
        Ok(record)
    }

    fn add_tree(&mut self, dir: &Path, prefix: &str) -> Result<()> {
        for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
            let entry = entry.map_err(|e| Error::io(dir, e))?;
            let file_name = entry.file_name();
            let Some(name) = recordable(&file_name) else { continue };
            let rel = format!("{prefix}{name}");
            let kind = entry.file_type().map_err(|e| Error::io(entry.path(), e))?;
            if kind.is_dir() {
                self.add_tree(&entry.path(), &format!("{rel}/"))?;
            } else if kind.is_file() && rel != RECORD {
                self.files.insert(rel, hash_file(&entry.path()).map_err(|e| Error::io(entry.path(), e))?);
            }
        }
        Ok(())
    }

    /// Records `rel` with the content `path` has now.
    pub fn add(&mut self, rel: &str, path: &Path) -> Result<()> {
        if recordable(std::ffi::OsStr::new(rel)).is_some() {
            self.files.insert(rel.to_string(), hash_file(path).map_err(|e| Error::io(path, e))?);
        }
        Ok(())
    }

    /// Keeps only the paths for which `keep` holds.
    pub fn retain(&mut self, mut keep: impl FnMut(&str) -> bool) {
        self.files.retain(|p, _| keep(p));
    }

    /// Forgets `rel`.
    pub fn remove(&mut self, rel: &str) {
        self.files.remove(rel);
    }

    /// The recorded paths.
    pub fn paths(&self) -> impl Iterator<Item = &str> {
        self.files.keys().map(String::as_str)
    }

    /// Whether the tool wrote something inside the folder `rel` (a path prefix).
    pub fn holds_inside(&self, rel: &str) -> bool {
        let prefix = format!("{rel}/");
        self.files.range(prefix.clone()..).next().is_some_and(|(p, _)| p.starts_with(&prefix))
    }

    /// Whether `dir/rel` is the tool's: a regular file (not a link), recorded, with the
    /// content it was recorded with.
    pub fn owns(&self, dir: &Path, rel: &str) -> bool {
        let Some(recorded) = self.files.get(rel) else { return false };
        let path = dir.join(rel);
        std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) && hash_file(&path).is_ok_and(|h| h == *recorded)
    }

    /// The sealed text of the record.
    fn text(&self) -> String {
        let mut body = format!("{HEADER}\n");
        for (path, hash) in &self.files {
            body.push_str(&format!("{} {path}\n", seal::hex(hash)));
        }
        seal::close(&body)
    }

    /// Writes the record into `dir`, atomically.
    pub fn write(&self, dir: &Path) -> Result<()> {
        super::write_atomic(&dir.join(RECORD), self.text().as_bytes())
    }
}

/// Who owns the entries of an existing folder `dir` that a staged folder is about to
/// replace: its record where it has a valid one, else the output's legacy rule.
pub struct Owner<'a> {
    dir: &'a Path,
    staged: &'a Path,
    record: Option<Record>,
    claim: &'a Claim,
}

impl<'a> Owner<'a> {
    pub fn of(dir: &'a Path, staged: &'a Path, claim: &'a Claim) -> Owner<'a> {
        Owner { dir, staged, record: Record::read(dir), claim }
    }

    /// Whether the regular file at `rel` may be replaced or removed.
    pub fn owns(&self, rel: &str) -> bool {
        let regular = || std::fs::symlink_metadata(self.dir.join(rel)).is_ok_and(|m| m.is_file());
        if self.claim.fixed.contains(rel) {
            return regular();
        }
        match &self.record {
            Some(record) => record.owns(self.dir, rel),
            None => {
                let listed = match &self.claim.legacy {
                    Legacy::Paths(paths) => paths.contains(rel),
                    Legacy::Rewritten => self.staged.join(rel).is_file(),
                };
                listed && regular()
            }
        }
    }

    /// Whether the folder `rel` may hold files of the tool's, so that its entries are judged
    /// one by one rather than kept whole.
    pub fn may_hold_ours(&self, rel: &str) -> bool {
        self.record.as_ref().is_none_or(|record| record.holds_inside(rel))
    }

    /// Whether the folder `rel`, emptied of the tool's files, was the tool's own (so it goes
    /// with them); without a record every folder is kept.
    pub fn owns_folder(&self, rel: &str) -> bool {
        self.record.as_ref().is_some_and(|record| record.holds_inside(rel))
    }
}

/// A name the record can hold: UTF-8 without line breaks (the tool never writes others).
fn recordable(name: &std::ffi::OsStr) -> Option<&str> {
    name.to_str().filter(|n| !n.contains(['\n', '\r']))
}

/// SHA-256 of a regular file's content, read without blocking (a FIFO never stalls it).
fn hash_file(path: &Path) -> std::io::Result<[u8; 32]> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let mut file = options.open(path)?;
    if !file.metadata()?.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
    }
    Ok(hasher.finalize().into())
}

fn unhex(s: &str) -> Option<[u8; 32]> {
    let bytes = s.as_bytes();
    if bytes.len() != 64 {
        return None;
    }
    let mut out = [0u8; 32];
    for (k, pair) in bytes.chunks(2).enumerate() {
        out[k] = u8::from_str_radix(std::str::from_utf8(pair).ok()?, 16).ok()?;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_owns_only_unchanged_recorded_regular_files() {
        let root = tempfile::tempdir().unwrap();
        let d = root.path();
        std::fs::create_dir(d.join("sub")).unwrap();
        std::fs::write(d.join("material.json"), "ours").unwrap();
        std::fs::write(d.join("sub/a.png"), "ours too").unwrap();
        let record = Record::of_tree(d).unwrap();
        record.write(d).unwrap();
        std::fs::write(d.join("notes.txt"), "user").unwrap();
        let record = Record::read(d).expect("sealed record reads back");
        assert!(record.owns(d, "material.json") && record.owns(d, "sub/a.png"));
        assert!(!record.owns(d, "notes.txt") && !record.owns(d, RECORD));
        assert!(record.holds_inside("sub") && !record.holds_inside("su"));
        // Edited since: the user's now.
        std::fs::write(d.join("material.json"), "edited").unwrap();
        assert!(!record.owns(d, "material.json"));
    }

    #[test]
    fn a_forged_or_altered_record_is_no_record() {
        let root = tempfile::tempdir().unwrap();
        let d = root.path();
        std::fs::write(d.join("notes.txt"), "user").unwrap();
        Record::of_tree(d).unwrap().write(d).unwrap();
        let text = std::fs::read_to_string(d.join(RECORD)).unwrap();
        assert!(Record::read(d).is_some());
        // The same lines with another seal, or one line changed: refused.
        std::fs::write(d.join(RECORD), text.replace("seal ", "seal 0")).unwrap();
        assert!(Record::read(d).is_none());
        std::fs::write(d.join(RECORD), text.replace("notes.txt", "other.txt")).unwrap();
        assert!(Record::read(d).is_none());
    }
}
