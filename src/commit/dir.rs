//! A directory written whole: staged under a temporary name beside its target, then put in
//! its place in one atomic step, carrying over every entry of the old one that is the user's
//! ([`super::owned`]).

use std::path::{Path, PathBuf};

use super::owned::{Claim, Owner, Record, RECORD};
use super::{parse_temp, remove_any, replace_dir, retarget_error, temp_sibling};
use crate::error::{Error, Result};

/// A directory being written under a temporary name beside its target, committed whole
/// ([`StagedDir::commit`]) or removed when dropped uncommitted.
pub struct StagedDir {
    tmp: PathBuf,
    target: PathBuf,
    claim: Claim,
    /// Files this run read (its inputs): never removed, even where they are the tool's.
    inputs: Vec<PathBuf>,
    committed: bool,
}

impl StagedDir {
    /// Starts a directory for `target` (its parent is created if missing). At commit, the
    /// old `target`'s files are replaced or removed only where `claim` says they are the
    /// tool's; everything else is kept.
    pub fn new(target: &Path, claim: Claim) -> Result<StagedDir> {
        let parent = super::parent_of(target);
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        let tmp = temp_sibling(target);
        std::fs::create_dir(&tmp).map_err(|e| Error::io(target, e))?;
        Ok(StagedDir { tmp, target: target.to_path_buf(), claim, inputs: Vec::new(), committed: false })
    }

    /// Files this run reads: kept even where they are the tool's and the new output does not
    /// rewrite them (a refit from `MAT/scene.gltf` into `MAT`).
    pub fn keep_inputs<'p>(&mut self, inputs: impl IntoIterator<Item = &'p Path>) {
        self.inputs.extend(inputs.into_iter().filter_map(|p| p.canonicalize().ok()));
    }

    /// The temporary directory to write into.
    pub fn path(&self) -> &Path {
        &self.tmp
    }

    /// The directory it will become.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Writes the file `name` with `write` (given the temporary path); errors name the file
    /// in the target directory, not the temporary one.
    pub fn write(&self, name: &str, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        write(&self.tmp.join(name)).map_err(|e| retarget_error(e, &self.tmp, &self.target))
    }

    /// Writes into the staged directory with `write` (given its temporary path); errors name
    /// the target directory, not the temporary one.
    pub fn fill(&self, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        write(&self.tmp).map_err(|e| retarget_error(e, &self.tmp, &self.target))
    }

    /// Records what was staged as the tool's, carries over the user's entries of the old
    /// directory (hard links, so nothing is copied), and replaces it in one atomic step. A
    /// user's entry at a name the new output also writes stops the commit, with one line,
    /// before anything changes.
    pub fn commit(mut self) -> Result<()> {
        Record::of_tree(&self.tmp)?.write(&self.tmp)?;
        if std::fs::symlink_metadata(&self.target).is_ok_and(|m| m.is_dir()) {
            let owner = Owner::of(&self.target, &self.tmp, &self.claim);
            self.keep_users_entries(&owner, Path::new(""))?;
        }
        replace_dir(&self.tmp, &self.target)?;
        self.committed = true;
        Ok(())
    }

    /// Carries every entry of the old directory's folder `rel` that is not the tool's into
    /// the staged directory.
    fn keep_users_entries(&self, owner: &Owner, rel: &Path) -> Result<()> {
        let from = self.target.join(rel);
        for entry in std::fs::read_dir(&from).map_err(|e| Error::io(&from, e))? {
            let entry = entry.map_err(|e| Error::io(&from, e))?;
            let name = entry.file_name();
            // The old record is replaced by the new; temporaries are the sweep's.
            let top = rel.as_os_str().is_empty();
            if top && (parse_temp(&name).is_some() || (name == RECORD && entry.file_type().is_ok_and(|t| t.is_file()))) {
                continue;
            }
            self.keep_entry(owner, &rel.join(&name), &entry.path())?;
        }
        Ok(())
    }

    fn keep_entry(&self, owner: &Owner, rel: &Path, from: &Path) -> Result<()> {
        let meta = std::fs::symlink_metadata(from).map_err(|e| Error::io(from, e))?;
        let to = self.tmp.join(rel);
        let staged = std::fs::symlink_metadata(&to).ok();
        // A name the record cannot hold is never the tool's.
        let key = rel.to_str().filter(|k| !k.contains(['\n', '\r']));
        if meta.is_dir() {
            match staged {
                Some(s) if s.is_dir() => return self.keep_users_entries(owner, rel),
                Some(_) => return Err(self.collision(rel)),
                None if key.is_some_and(|k| owner.may_hold_ours(k)) => return self.keep_folder(owner, rel, &meta),
                None => {}
            }
        } else if meta.is_file() && key.is_some_and(|k| owner.owns(k)) {
            if staged.is_some() || !self.is_input(from) {
                return Ok(());
            }
        } else if staged.is_some() {
            return Err(self.collision(rel));
        }
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(self.target.join(rel), e))?;
        }
        link_tree(from, &to).map_err(|e| Error::io(from, e))
    }

    /// A folder of the old directory the new one lacks, which may hold the tool's files:
    /// kept with the user's entries, and gone if it was the tool's and holds nothing else.
    fn keep_folder(&self, owner: &Owner, rel: &Path, meta: &std::fs::Metadata) -> Result<()> {
        let to = self.tmp.join(rel);
        std::fs::create_dir_all(&to).map_err(|e| Error::io(self.target.join(rel), e))?;
        let _ = std::fs::set_permissions(&to, meta.permissions());
        self.keep_users_entries(owner, rel)?;
        let empty = std::fs::read_dir(&to).map(|mut d| d.next().is_none()).unwrap_or(false);
        if empty && rel.to_str().is_some_and(|k| owner.owns_folder(k)) {
            let _ = std::fs::remove_dir(&to);
        }
        Ok(())
    }

    fn is_input(&self, path: &Path) -> bool {
        path.canonicalize().is_ok_and(|p| self.inputs.contains(&p))
    }

    fn collision(&self, rel: &Path) -> Error {
        Error::input(format!(
            "{} is not a file brdfpaint wrote (or it changed since); not replacing it: move it away or choose another output",
            self.target.join(rel).display()
        ))
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            remove_any(&self.tmp);
        }
    }
}

/// Recreates `from` at `to`: files as hard links (a copy where linking fails), directories
/// entry by entry with their permissions, symbolic links as links.
fn link_tree(from: &Path, to: &Path) -> std::io::Result<()> {
    let meta = std::fs::symlink_metadata(from)?;
    if meta.is_dir() {
        std::fs::create_dir(to)?;
        for entry in std::fs::read_dir(from)? {
            let entry = entry?;
            link_tree(&entry.path(), &to.join(entry.file_name()))?;
        }
        std::fs::set_permissions(to, meta.permissions())
    } else if meta.file_type().is_symlink() {
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(std::fs::read_link(from)?, to)
        }
        #[cfg(not(unix))]
        {
            std::fs::copy(from, to).map(|_| ())
        }
    } else if std::fs::hard_link(from, to).is_ok() {
        Ok(())
    } else {
        std::fs::copy(from, to).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::commit::Legacy;
    use std::collections::BTreeSet;

    fn legacy(names: &[&str]) -> Claim {
        Claim::new(&[], Legacy::Paths(names.iter().map(|s| s.to_string()).collect::<BTreeSet<_>>()))
    }

    #[test]
    fn a_staged_directory_replaces_ours_and_keeps_the_users_files() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("mat");
        let staged = StagedDir::new(&target, legacy(&[])).unwrap();
        staged.write("material.json", |p| super::super::write_atomic(p, b"old")).unwrap();
        staged.write("term1-factor0-l.exr", |p| super::super::write_atomic(p, b"old")).unwrap();
        staged.commit().unwrap();
        std::fs::write(target.join("notes.txt"), "mine").unwrap();
        std::fs::create_dir(target.join("paintings")).unwrap();
        std::fs::write(target.join("paintings/p.png"), "art").unwrap();
        std::fs::create_dir(target.join("term1-sketches.exr")).unwrap();
        let staged = StagedDir::new(&target, legacy(&[])).unwrap();
        staged.write("material.json", |p| super::super::write_atomic(p, b"new")).unwrap();
        staged.commit().unwrap();
        assert_eq!(std::fs::read_to_string(target.join("material.json")).unwrap(), "new");
        // The tool's table that the new material does not write is gone; the user's stay.
        assert!(!target.join("term1-factor0-l.exr").exists());
        assert_eq!(std::fs::read_to_string(target.join("notes.txt")).unwrap(), "mine");
        assert_eq!(std::fs::read_to_string(target.join("paintings/p.png")).unwrap(), "art");
        assert!(target.join("term1-sketches.exr").is_dir());
        assert!(super::super::temporaries(root.path()).is_empty());
        // Dropped uncommitted: nothing is left.
        let staged = StagedDir::new(&target, legacy(&[])).unwrap();
        staged.write("material.json", |p| super::super::write_atomic(p, b"newer")).unwrap();
        drop(staged);
        assert!(super::super::temporaries(root.path()).is_empty());
        assert_eq!(std::fs::read_to_string(target.join("material.json")).unwrap(), "new");
    }

    #[test]
    fn a_users_file_at_a_name_the_output_writes_stops_the_commit() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("mat");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("material.json"), "legacy").unwrap();
        std::fs::write(target.join("scene.gltf"), "the user's scene").unwrap();
        let staged = StagedDir::new(&target, legacy(&["material.json"])).unwrap();
        staged.write("material.json", |p| super::super::write_atomic(p, b"new")).unwrap();
        staged.write("scene.gltf", |p| super::super::write_atomic(p, b"ours")).unwrap();
        let e = staged.commit().unwrap_err().to_string();
        assert!(e.contains("scene.gltf") && !e.contains('\n'), "{e}");
        assert_eq!(std::fs::read_to_string(target.join("scene.gltf")).unwrap(), "the user's scene");
        assert_eq!(std::fs::read_to_string(target.join("material.json")).unwrap(), "legacy");
        assert!(super::super::temporaries(root.path()).is_empty());
    }

    #[test]
    fn nested_folders_keep_the_users_files_and_lose_the_tools() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("demo");
        let staged = StagedDir::new(&target, Claim::new(&[], Legacy::Rewritten)).unwrap();
        std::fs::create_dir_all(staged.path().join("renders/old")).unwrap();
        std::fs::write(staged.path().join("renders/old/a.png"), "ours").unwrap();
        std::fs::write(staged.path().join("renders/b.png"), "ours").unwrap();
        staged.commit().unwrap();
        std::fs::write(target.join("renders/mine.png"), "user").unwrap();
        let staged = StagedDir::new(&target, Claim::new(&[], Legacy::Rewritten)).unwrap();
        std::fs::create_dir_all(staged.path().join("renders")).unwrap();
        std::fs::write(staged.path().join("renders/b.png"), "ours, new").unwrap();
        staged.commit().unwrap();
        assert_eq!(std::fs::read_to_string(target.join("renders/b.png")).unwrap(), "ours, new");
        assert_eq!(std::fs::read_to_string(target.join("renders/mine.png")).unwrap(), "user");
        assert!(!target.join("renders/old").exists());
    }
}
