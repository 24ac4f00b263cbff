//! A set of files in one directory (a turntable's frames) renamed into place together, by a
//! sealed journal that a run killed half-way leaves for the next one to complete.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use super::owned::Record;
use super::{parent_of, parse_temp, retarget_error, seal, sync_dir, temp_path, temp_sibling, write_atomic, Role};
use crate::error::{Error, Result};

/// The names of one frame sequence: `{stem}-{index}.{ext}`, the index of 3 digits or more.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sequence {
    stem: String,
    ext: String,
}

impl Sequence {
    pub fn new(stem: &str, ext: &str) -> Sequence {
        Sequence { stem: stem.into(), ext: ext.into() }
    }

    /// Frame `k` of `frames`: the index zero-padded to 3 digits, more when there are more frames.
    pub fn name(&self, k: usize, frames: usize) -> String {
        let digits = (frames.saturating_sub(1)).to_string().len().max(3);
        format!("{}-{k:0digits$}.{}", self.stem, self.ext)
    }

    /// Whether `name` is a frame of this sequence (any length).
    pub fn contains(&self, name: &str) -> bool {
        let index = name.strip_prefix(&self.stem).and_then(|r| r.strip_prefix('-')).and_then(|r| r.strip_suffix(&self.ext)).and_then(|r| r.strip_suffix('.'));
        index.is_some_and(|i| i.len() >= 3 && i.bytes().all(|b| b.is_ascii_digit()))
    }
}

/// A set of files written under temporary names beside their targets (all in one
/// directory), renamed into place together by [`StagedFiles::commit`] or removed when dropped
/// uncommitted.
#[derive(Default)]
pub struct StagedFiles {
    files: Vec<(PathBuf, PathBuf)>,
    /// The sequence the files are frames of, whose earlier frames the tool owns.
    sequence: Option<Sequence>,
    committed: bool,
}

impl StagedFiles {
    /// Files named by the user: each replaces whatever file has its name.
    pub fn new() -> StagedFiles {
        StagedFiles::default()
    }

    /// The frames of `sequence`, recorded in their directory's ownership record
    /// ([`super::owned`]): an existing frame is replaced only if the tool wrote it, and the
    /// tool's frames of a longer earlier run are removed, so the sequence on disk is the new
    /// one alone. (Without a record, as a version without records left it, frames of the
    /// sequence's names are replaced and none removed.)
    pub fn sequence(sequence: Sequence) -> StagedFiles {
        StagedFiles { files: Vec::new(), sequence: Some(sequence), committed: false }
    }

    /// Writes `target`'s content with `write` (given the temporary path); errors name
    /// `target`. Every target must be in the same directory as the first.
    pub fn add(&mut self, target: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        if let Some((_, first)) = self.files.first() {
            if parent_of(first) != parent_of(target) {
                return Err(Error::input(format!(
                    "{}: a set of outputs must share one directory ({})",
                    target.display(),
                    parent_of(first).display()
                )));
            }
        }
        // One sweep of the directory per set: a sequence of thousands of frames must not
        // list its directory once per frame.
        let tmp = if self.files.is_empty() { temp_sibling(target) } else { temp_path(target, Role::New) };
        self.files.push((tmp.clone(), target.to_path_buf()));
        write(&tmp).map_err(|e| retarget_error(e, &tmp, target))
    }

    /// Renames every file into place. One file is one rename; several are first listed in a
    /// journal, so that a run killed half-way is completed by the next one (module docs).
    pub fn commit(mut self) -> Result<()> {
        let Some((_, first)) = self.files.first() else { return Ok(()) };
        let dir = parent_of(first).to_path_buf();
        let claimed = match &self.sequence {
            Some(sequence) => Some(self.claim(&dir, sequence)?),
            None => None,
        };
        let journal = if self.files.len() > 1 { Some(self.write_journal(&dir)?) } else { None };
        for (tmp, target) in &self.files {
            if let Err(e) = std::fs::rename(tmp, target) {
                // Nothing can be rolled back (the old files are gone): finish what can be
                // finished by the next sweep, and say which file failed.
                return Err(Error::io(target, e));
            }
        }
        sync_dir(&dir);
        if let Some(journal) = journal {
            let _ = std::fs::remove_file(journal);
        }
        self.committed = true;
        if let Some((record, stale)) = claimed {
            remove_stale(&dir, record, &stale);
        }
        Ok(())
    }

    /// Checks that every existing target is the tool's, and records the new frames (before
    /// any rename, so a kill leaves them recorded). Returns the record and the tool's earlier
    /// frames that the new sequence does not rewrite, still recorded until removed.
    fn claim(&self, dir: &Path, sequence: &Sequence) -> Result<(Record, Vec<String>)> {
        let old = Record::read(dir);
        let name = |p: &Path| p.file_name().and_then(OsStr::to_str).unwrap_or_default().to_string();
        for (_, target) in &self.files {
            let owned = match &old {
                Some(record) => record.owns(dir, &name(target)),
                None => sequence.contains(&name(target)) && std::fs::symlink_metadata(target).is_ok_and(|m| m.is_file()),
            };
            if !owned && std::fs::symlink_metadata(target).is_ok() {
                return Err(Error::input(format!(
                    "{} is not a frame brdfpaint wrote (or it changed since); not replacing it: move it away or choose another output",
                    target.display()
                )));
            }
        }
        let mut record = old.clone().unwrap_or_default();
        // Entries whose file is gone are forgotten, so a record does not grow forever.
        record.retain(|p| dir.join(p).exists());
        for (tmp, target) in &self.files {
            record.add(&name(target), tmp)?;
        }
        let new: std::collections::HashSet<String> = self.files.iter().map(|(_, t)| name(t)).collect();
        let stale = old
            .map(|r| r.paths().filter(|p| sequence.contains(p) && !new.contains(*p) && r.owns(dir, p)).map(String::from).collect())
            .unwrap_or_default();
        record.write(dir)?;
        Ok((record, stale))
    }

    /// Writes the journal (pairs of temporary and target names, one pair a line, sealed:
    /// [`seal`]) under a temporary name and renames it to its `seq` name, so it is whole
    /// when it exists.
    fn write_journal(&self, dir: &Path) -> Result<PathBuf> {
        let mut text = String::new();
        for (tmp, target) in &self.files {
            let name = |p: &Path| p.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            text.push_str(&format!("{}\t{}\n", name(tmp), name(target)));
        }
        let text = seal::close(&text);
        let (_, first) = &self.files[0];
        let journal = temp_path(first, Role::Seq);
        write_atomic(&journal, text.as_bytes()).map_err(|e| retarget_error(e, &journal, first))?;
        sync_dir(dir);
        Ok(journal)
    }
}

impl Drop for StagedFiles {
    fn drop(&mut self) {
        if !self.committed {
            for (tmp, _) in &self.files {
                let _ = std::fs::remove_file(tmp);
            }
        }
    }
}

/// Removes the tool's earlier frames the new sequence did not rewrite, then forgets them; a
/// kill between leaves them recorded, for the next run of the sequence to remove.
fn remove_stale(dir: &Path, mut record: Record, stale: &[String]) {
    if stale.is_empty() {
        return;
    }
    for name in stale {
        if std::fs::remove_file(dir.join(name)).is_ok() {
            record.remove(name);
        }
    }
    let _ = record.write(dir);
}

/// Completes the renames a journal of the dead process `pid` lists, then removes it. Only a
/// journal sealed by this user's brdfpaint is followed, and only for pairs that rename a
/// temporary of that process, of role `new`, to the name that temporary stands for: a
/// planted journal cannot move or overwrite a user's file.
pub(super) fn complete_journal(dir: &Path, journal: &Path, pid: u32) {
    if let Some(pairs) = sealed_pairs(journal) {
        for (tmp, target) in pairs {
            let ours = parse_temp(OsStr::new(&tmp)).is_some_and(|(p, role, t)| p == pid && role == Role::New && t == target);
            if !ours || target.contains('/') || target.is_empty() || target == ".." {
                continue;
            }
            let tmp = dir.join(tmp);
            if tmp.exists() && std::fs::rename(&tmp, dir.join(target)).is_err() {
                return;
            }
        }
    }
    let _ = std::fs::remove_file(journal);
}

/// The pairs of a sealed journal; `None` if it is not one.
fn sealed_pairs(journal: &Path) -> Option<Vec<(String, String)>> {
    let bytes = crate::fsio::read_regular(journal, 64 << 20).ok()?;
    let text = String::from_utf8(bytes).ok()?;
    seal::open(&text)?
        .lines().map(|l| l.split_once('\t').map(|(a, b)| (a.to_string(), b.to_string()))).collect()
}

