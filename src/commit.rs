//! Whole-or-nothing outputs: a file, a directory (a material, a sheet, a demo) or a set of
//! files (a turntable sequence) appears complete or not at all, even if the process is
//! killed at any instruction.
//!
//! Everything is first written under a hidden temporary name beside the target,
//! `.brdfpaint-{pid}-{n}-{role}-{name}`, then committed:
//! - a file, or a directory where nothing is, by one `rename`;
//! - a directory over an existing one by one `renameat2(RENAME_EXCHANGE)` (Linux), which
//!   swaps the two atomically; the old one, now under the temporary name, is then removed.
//!   Where the file system cannot exchange, the old directory is first renamed aside (role
//!   `old`), and a run killed between the two renames is repaired by the next one, which
//!   puts it back;
//! - a set of files in one directory by a journal (role `seq`) written before the first
//!   rename: a run killed while renaming is completed by the next one.
//!
//! Every run sweeps the directory it writes into ([`sweep_stale`]): temporary names of
//! processes that no longer run are removed, repaired or completed. A temporary name of a
//! live process is never touched.

use std::ffi::{OsStr, OsString};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Every temporary name starts with this.
const PREFIX: &str = ".brdfpaint-";

/// What a temporary name holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// Content being written (or, after an exchange, the old content being removed).
    New,
    /// An old directory moved aside while its replacement is renamed in.
    Old,
    /// The journal of a set of renames.
    Seq,
}

impl Role {
    fn name(self) -> &'static str {
        match self {
            Role::New => "new",
            Role::Old => "old",
            Role::Seq => "seq",
        }
    }
}

/// A hidden temporary path beside `path` (same directory, so renames are atomic), unique
/// in this process, recognizable as ours by [`sweep_stale`].
fn temp_path(path: &Path, role: Role) -> PathBuf {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let name = path.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!("{PREFIX}{}-{n}-{}-{name}", std::process::id(), role.name()))
}

/// A hidden temporary path beside `path` for content being written. Stale temporaries of
/// killed runs in the same directory are swept first.
pub fn temp_sibling(path: &Path) -> PathBuf {
    sweep_stale(parent_of(path));
    temp_path(path, Role::New)
}

/// The directory `path` is in (`.` for a bare name).
fn parent_of(path: &Path) -> &Path {
    path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// A parsed temporary name: the process that made it, its role, and the target's name.
fn parse_temp(name: &OsStr) -> Option<(u32, Role, String)> {
    let rest = name.to_str()?.strip_prefix(PREFIX)?;
    let mut parts = rest.splitn(4, '-');
    let pid: u32 = parts.next()?.parse().ok()?;
    let _n: u64 = parts.next()?.parse().ok()?;
    let role = match parts.next()? {
        "new" => Role::New,
        "old" => Role::Old,
        "seq" => Role::Seq,
        _ => return None,
    };
    Some((pid, role, parts.next()?.to_string()))
}

/// Whether process `pid` runs (or may: a process we may not signal exists).
fn alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    #[cfg(unix)]
    {
        let Ok(pid) = libc::pid_t::try_from(pid) else { return false };
        // SAFETY: signal 0 only checks that the process exists.
        if unsafe { libc::kill(pid, 0) } == 0 {
            return true;
        }
        std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
    }
    #[cfg(not(unix))]
    {
        true
    }
}

/// Removes, repairs or completes the temporaries of dead processes in `dir` (module docs).
/// Best effort: what cannot be cleaned now is left for a later run.
pub fn sweep_stale(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut stale: Vec<(Role, String, PathBuf)> = entries
        .flatten()
        .filter_map(|e| {
            let (pid, role, target) = parse_temp(&e.file_name())?;
            (!alive(pid)).then(|| (role, target, e.path()))
        })
        .collect();
    // Journals first (they name `new` temporaries to complete), then directories moved aside
    // (to put back), then the rest.
    stale.sort_by_key(|(role, _, _)| match role {
        Role::Seq => 0,
        Role::Old => 1,
        Role::New => 2,
    });
    for (role, target, path) in stale {
        match role {
            Role::Seq => {
                complete_journal(dir, &path);
            }
            Role::Old => {
                let target = dir.join(&target);
                if std::fs::symlink_metadata(&target).is_err() {
                    let _ = std::fs::rename(&path, &target);
                } else {
                    remove_any(&path);
                }
            }
            Role::New => remove_any(&path),
        }
    }
}

/// Removes a file or a directory tree, ignoring errors (a later sweep retries).
fn remove_any(path: &Path) {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => {
            let _ = std::fs::remove_dir_all(path);
        }
        Ok(_) => {
            let _ = std::fs::remove_file(path);
        }
        Err(_) => {}
    }
}

/// Flushes a directory's entries (renames) to disk; best effort.
fn sync_dir(dir: &Path) {
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Writes a file atomically: the bytes go to a temporary file beside `path`, which is then
/// renamed over it, so a reader never sees a half-written file. Errors name `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temp_sibling(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}

/// Swaps two paths atomically (Linux `renameat2(RENAME_EXCHANGE)`).
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let cstr = |p: &Path| std::ffi::CString::new(p.as_os_str().as_bytes()).map_err(std::io::Error::other);
    let (a, b) = (cstr(a)?, cstr(b)?);
    // SAFETY: two NUL-terminated paths that live across the call; the syscall only reads them.
    let r = unsafe {
        libc::syscall(libc::SYS_renameat2, libc::AT_FDCWD, a.as_ptr(), libc::AT_FDCWD, b.as_ptr(), libc::RENAME_EXCHANGE)
    };
    if r == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> std::io::Result<()> {
    Err(std::io::Error::from(std::io::ErrorKind::Unsupported))
}

/// Whether an exchange failed because the system or file system cannot do it (rather than
/// because of the paths).
fn exchange_unsupported(e: &std::io::Error) -> bool {
    #[cfg(unix)]
    if matches!(e.raw_os_error(), Some(libc::EINVAL | libc::ENOSYS | libc::EOPNOTSUPP)) {
        return true;
    }
    e.kind() == std::io::ErrorKind::Unsupported
}

/// Puts the finished directory `tmp` (a sibling) at `dir`: by one rename where nothing is,
/// else by an atomic exchange, the old directory then removed (module docs). Errors name
/// `dir`.
pub fn replace_dir(tmp: &Path, dir: &Path) -> Result<()> {
    match std::fs::symlink_metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            std::fs::rename(tmp, dir).map_err(|e| Error::io(dir, e))?;
            sync_dir(parent_of(dir));
            return Ok(());
        }
        Err(e) => return Err(Error::io(dir, e)),
        // An exchange would put a file or link that appeared meanwhile under a temporary
        // name, to be removed: never replace anything but a directory.
        Ok(m) if !m.is_dir() => {
            return Err(Error::input(format!("{} exists and is not a directory; not overwriting it", dir.display())));
        }
        Ok(_) => {}
    }
    match exchange(tmp, dir) {
        // `tmp` now holds the old directory; a kill before it is removed leaves it to the
        // next sweep.
        Ok(()) => {
            sync_dir(parent_of(dir));
            remove_any(tmp);
            Ok(())
        }
        Err(e) if exchange_unsupported(&e) => {
            let aside = temp_path(dir, Role::Old);
            std::fs::rename(dir, &aside).map_err(|e| Error::io(dir, e))?;
            // A kill here leaves `dir` missing and `aside` of a dead process: the next sweep
            // renames it back.
            if let Err(e) = std::fs::rename(tmp, dir) {
                let _ = std::fs::rename(&aside, dir);
                return Err(Error::io(dir, e));
            }
            sync_dir(parent_of(dir));
            remove_any(&aside);
            Ok(())
        }
        Err(e) => Err(Error::io(dir, e)),
    }
}

/// Whether an output directory's path is free to write: nothing there or an empty directory
/// (`true`), or a directory holding files (`false`, the caller decides whether they are its
/// own). Anything else there, a file or a link, is refused with one line. Our own stale
/// temporaries inside do not count.
pub fn output_dir_is_fresh(dir: &Path) -> Result<bool> {
    let meta = match std::fs::symlink_metadata(dir) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(true),
        Err(e) => return Err(Error::io(dir, e)),
    };
    if !meta.is_dir() {
        return Err(Error::input(format!("{} exists and is not a directory; not overwriting it", dir.display())));
    }
    sweep_stale(dir);
    Ok(std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?.next().is_none())
}

/// Puts the finished directory `tmp` (a sibling) at `dir`, which is missing or an empty
/// directory (checked by the caller): one rename, which replaces an empty directory.
pub fn move_into_fresh(tmp: &Path, dir: &Path) -> Result<()> {
    replace_dir(tmp, dir)
}

/// Replaces the directory `dir` by the finished directory `tmp` (a sibling, same file
/// system) atomically ([`replace_dir`]).
pub fn swap_dir(tmp: &Path, dir: &Path) -> Result<()> {
    replace_dir(tmp, dir)
}

/// An error about a temporary path, told about the path it stands for.
pub fn retarget_error(e: Error, tmp: &Path, path: &Path) -> Error {
    let swap = |s: String| s.replace(&tmp.display().to_string(), &path.display().to_string());
    match e {
        Error::Io { path: p, source } => Error::io(swap(p.display().to_string()), source),
        Error::Format { path: p, reason } => Error::format(swap(p.display().to_string()), swap(reason)),
        Error::Input(m) => Error::Input(swap(m)),
        Error::Numeric(m) => Error::Numeric(swap(m)),
        Error::Gl(m) => Error::Gl(swap(m)),
    }
}

/// Which entries of an existing target directory are the tool's own (replaced by the
/// commit); all others are the user's and are kept.
pub type Ours = Box<dyn Fn(&OsStr) -> bool>;

/// A directory being written under a temporary name beside its target, committed whole
/// ([`StagedDir::commit`]) or removed when dropped uncommitted.
pub struct StagedDir {
    tmp: PathBuf,
    target: PathBuf,
    ours: Ours,
    committed: bool,
}

impl StagedDir {
    /// Starts a directory for `target` (its parent is created if missing). At commit, the
    /// entries of an existing `target` for which `ours` is false are kept.
    pub fn new(target: &Path, ours: Ours) -> Result<StagedDir> {
        let parent = parent_of(target);
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        let tmp = temp_sibling(target);
        std::fs::create_dir(&tmp).map_err(|e| Error::io(target, e))?;
        Ok(StagedDir { tmp, target: target.to_path_buf(), ours, committed: false })
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

    /// Replaces `target` by the staged directory in one atomic step, carrying over the
    /// user's entries of the old one (hard links, so nothing is copied).
    pub fn commit(mut self) -> Result<()> {
        self.keep_users_entries()?;
        replace_dir(&self.tmp, &self.target)?;
        self.committed = true;
        Ok(())
    }

    /// Links every entry of the existing target that is not ours, and not already staged,
    /// into the staged directory, so it survives the exchange.
    fn keep_users_entries(&self) -> Result<()> {
        let Ok(entries) = std::fs::read_dir(&self.target) else { return Ok(()) };
        for entry in entries {
            let entry = entry.map_err(|e| Error::io(&self.target, e))?;
            let name = entry.file_name();
            if (self.ours)(&name) || parse_temp(&name).is_some() {
                continue;
            }
            let to = self.tmp.join(&name);
            if std::fs::symlink_metadata(&to).is_ok() {
                continue;
            }
            link_tree(&entry.path(), &to).map_err(|e| Error::io(entry.path(), e))?;
        }
        Ok(())
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
/// entry by entry, symbolic links as links.
fn link_tree(from: &Path, to: &Path) -> std::io::Result<()> {
    let meta = std::fs::symlink_metadata(from)?;
    if meta.is_dir() {
        std::fs::create_dir(to)?;
        for entry in std::fs::read_dir(from)? {
            let entry = entry?;
            link_tree(&entry.path(), &to.join(entry.file_name()))?;
        }
        Ok(())
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

/// A set of files written under temporary names beside their targets (all in one
/// directory), renamed into place together by [`StagedFiles::commit`] or removed when dropped
/// uncommitted.
#[derive(Default)]
pub struct StagedFiles {
    files: Vec<(PathBuf, PathBuf)>,
    committed: bool,
}

impl StagedFiles {
    pub fn new() -> StagedFiles {
        StagedFiles::default()
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
        Ok(())
    }

    /// Writes the journal (pairs of temporary and target names, one pair a line) under a
    /// temporary name and renames it to its `seq` name, so it is whole when it exists.
    fn write_journal(&self, dir: &Path) -> Result<PathBuf> {
        let mut text = String::new();
        for (tmp, target) in &self.files {
            let name = |p: &Path| p.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            text.push_str(&format!("{}\t{}\n", name(tmp), name(target)));
        }
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

/// Completes the renames a journal lists (those whose temporary still exists), then
/// removes it.
fn complete_journal(dir: &Path, journal: &Path) {
    let Ok(text) = std::fs::read_to_string(journal) else { return };
    for line in text.lines() {
        let Some((tmp, target)) = line.split_once('\t') else { continue };
        // Names only: a journal never points outside its directory.
        if [tmp, target].iter().any(|n| n.contains('/') || *n == ".." || n.is_empty()) {
            continue;
        }
        let tmp = dir.join(tmp);
        if tmp.exists() && std::fs::rename(&tmp, dir.join(target)).is_err() {
            return;
        }
    }
    let _ = std::fs::remove_file(journal);
}

/// The names of the temporaries in `dir` (for tests and checks: after a successful run,
/// and after a sweep, there are none of dead processes).
pub fn temporaries(dir: &Path) -> Vec<OsString> {
    std::fs::read_dir(dir)
        .map(|d| d.flatten().map(|e| e.file_name()).filter(|n| parse_temp(n).is_some()).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temp_names_parse_back() {
        let p = temp_path(Path::new("/x/my-mat"), Role::Old);
        let (pid, role, target) = parse_temp(p.file_name().unwrap()).unwrap();
        assert_eq!((pid, role, target.as_str()), (std::process::id(), Role::Old, "my-mat"));
        assert!(parse_temp(OsStr::new(".brdfpaint-notes")).is_none());
        assert!(parse_temp(OsStr::new("material.json")).is_none());
    }

    /// A pid that does not run: a child that has exited and been reaped.
    fn dead_pid() -> u32 {
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        pid
    }

    #[test]
    fn stale_temporaries_are_removed_repaired_or_completed() {
        let root = tempfile::tempdir().unwrap();
        let d = root.path();
        let dead = dead_pid();
        // A half-written directory of a dead run: removed.
        std::fs::create_dir(d.join(format!(".brdfpaint-{dead}-0-new-mat"))).unwrap();
        // An old directory moved aside, its target missing: put back.
        std::fs::create_dir(d.join(format!(".brdfpaint-{dead}-1-old-sheet"))).unwrap();
        std::fs::write(d.join(format!(".brdfpaint-{dead}-1-old-sheet/outline.png")), "old").unwrap();
        // A journal of two renames, one done: completed.
        std::fs::write(d.join("r-000.png"), "new0").unwrap();
        std::fs::write(d.join("r-001.png"), "old1").unwrap();
        std::fs::write(d.join(format!(".brdfpaint-{dead}-3-new-r-001.png")), "new1").unwrap();
        std::fs::write(
            d.join(format!(".brdfpaint-{dead}-4-seq-r-000.png")),
            format!(".brdfpaint-{dead}-2-new-r-000.png\tr-000.png\n.brdfpaint-{dead}-3-new-r-001.png\tr-001.png\n"),
        )
        .unwrap();
        // A live process's temporary: untouched.
        let live = temp_path(&d.join("x"), Role::New);
        std::fs::write(&live, "mine").unwrap();
        sweep_stale(d);
        assert_eq!(std::fs::read_to_string(d.join("sheet/outline.png")).unwrap(), "old");
        assert_eq!(std::fs::read_to_string(d.join("r-001.png")).unwrap(), "new1");
        assert_eq!(temporaries(d), vec![live.file_name().unwrap().to_os_string()]);
    }

    #[test]
    fn a_staged_directory_replaces_ours_and_keeps_the_users_files() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("mat");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("material.json"), "old").unwrap();
        std::fs::write(target.join("notes.txt"), "mine").unwrap();
        std::fs::create_dir(target.join("paintings")).unwrap();
        std::fs::write(target.join("paintings/p.png"), "art").unwrap();
        let staged = StagedDir::new(&target, Box::new(|n| n == "material.json")).unwrap();
        staged.write("material.json", |p| write_atomic(p, b"new")).unwrap();
        staged.commit().unwrap();
        assert_eq!(std::fs::read_to_string(target.join("material.json")).unwrap(), "new");
        assert_eq!(std::fs::read_to_string(target.join("notes.txt")).unwrap(), "mine");
        assert_eq!(std::fs::read_to_string(target.join("paintings/p.png")).unwrap(), "art");
        assert!(temporaries(root.path()).is_empty());
        // Dropped uncommitted: nothing is left.
        let staged = StagedDir::new(&target, Box::new(|_| true)).unwrap();
        staged.write("material.json", |p| write_atomic(p, b"newer")).unwrap();
        drop(staged);
        assert!(temporaries(root.path()).is_empty());
        assert_eq!(std::fs::read_to_string(target.join("material.json")).unwrap(), "new");
    }

    #[test]
    fn errors_name_the_target_not_the_temporary() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("out");
        let staged = StagedDir::new(&target, Box::new(|_| true)).unwrap();
        let e = staged.write("sub/x.png", |p| write_atomic(p, b"x")).unwrap_err().to_string();
        assert!(e.contains(&target.join("sub").display().to_string()) && !e.contains(".brdfpaint-"), "{e}");
    }
}
