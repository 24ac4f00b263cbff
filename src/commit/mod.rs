//! Whole-or-nothing outputs: a file, a directory (a material, a sheet, a demo) or a set of
//! files (a turntable sequence) appears complete or not at all, even if the process is
//! killed at any instruction; and no user's file is ever removed, renamed or overwritten on
//! the way ([`owned`]: only files the tool recorded writing, unchanged since, are replaced).
//!
//! Everything is first written under a hidden temporary name beside the target,
//! `.brdfpaint-{pid}-{n}-{role}-{name}`, then committed:
//! - a file, or a directory where nothing is, by one `rename`;
//! - a directory over an existing one by one `renameat2(RENAME_EXCHANGE)` (Linux), which
//!   swaps the two atomically; the old one, now under the temporary name, is then removed,
//!   after the user's entries in it were linked into the new one ([`StagedDir`]). Where the
//!   file system cannot exchange, the old directory is first renamed aside (role `old`), and
//!   a run killed between the two renames is repaired by the next one, which puts it back;
//! - a set of files in one directory by a sealed journal (role `seq`) written before the
//!   first rename: a run killed while renaming is completed by the next one ([`StagedFiles`]).
//!
//! Every run sweeps the directory it writes into ([`sweep_stale`]): temporary names of
//! processes that no longer run are removed, repaired or completed. A temporary name of a
//! live process is never touched, and the sweep touches no name but the temporaries': a
//! journal is followed only if the tool sealed it, and only to rename a temporary to the name
//! it stands for.

use std::ffi::{OsStr, OsString};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

mod dir;
mod files;
pub mod owned;
mod seal;

pub use dir::StagedDir;
pub use files::{Sequence, StagedFiles};
pub use owned::{Claim, Legacy, Record};

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
    let mut stale: Vec<(u32, Role, String, PathBuf)> = entries
        .flatten()
        .filter_map(|e| {
            let (pid, role, target) = parse_temp(&e.file_name())?;
            (!alive(pid)).then(|| (pid, role, target, e.path()))
        })
        .collect();
    // Journals first (they name `new` temporaries to complete), then directories moved aside
    // (to put back), then the rest.
    stale.sort_by_key(|(_, role, _, _)| match role {
        Role::Seq => 0,
        Role::Old => 1,
        Role::New => 2,
    });
    for (pid, role, target, path) in stale {
        match role {
            Role::Seq => files::complete_journal(dir, &path, pid),
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
            seal::close(&format!(".brdfpaint-{dead}-2-new-r-000.png\tr-000.png\n.brdfpaint-{dead}-3-new-r-001.png\tr-001.png\n")),
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
    fn a_planted_journal_moves_no_users_file() {
        let root = tempfile::tempdir().unwrap();
        let d = root.path();
        let dead = dead_pid();
        std::fs::write(d.join("precious.txt"), "precious").unwrap();
        std::fs::write(d.join("other.txt"), "other").unwrap();
        // Unsealed: ignored (and removed, as a temporary of a dead process).
        std::fs::write(d.join(format!(".brdfpaint-{dead}-0-seq-x")), "precious.txt\tother.txt\n").unwrap();
        // Sealed (as if copied from a journal of the tool's), but naming user files: the
        // pairs that are not a temporary of that process renamed to its own name are skipped.
        let forged = format!("precious.txt\tother.txt\n.brdfpaint-{dead}-9-new-other.txt\tprecious.txt\n");
        std::fs::write(d.join(format!(".brdfpaint-{dead}-1-seq-y")), seal::close(&forged)).unwrap();
        std::fs::write(d.join(format!(".brdfpaint-{dead}-9-new-other.txt")), "planted").unwrap();
        sweep_stale(d);
        assert_eq!(std::fs::read_to_string(d.join("precious.txt")).unwrap(), "precious");
        assert_eq!(std::fs::read_to_string(d.join("other.txt")).unwrap(), "other");
        assert!(temporaries(d).is_empty());
    }

    #[test]
    fn errors_name_the_target_not_the_temporary() {
        let root = tempfile::tempdir().unwrap();
        let target = root.path().join("out");
        let staged = StagedDir::new(&target, Claim::new(&[], Legacy::Rewritten)).unwrap();
        let e = staged.write("sub/x.png", |p| write_atomic(p, b"x")).unwrap_err().to_string();
        assert!(e.contains(&target.join("sub").display().to_string()) && !e.contains(".brdfpaint-"), "{e}");
    }
}
