//! Reading the files a user names, under one policy (README, "File access").
//!
//! - Only regular files are read. A FIFO, a device (`/dev/zero`), a socket or a directory is
//!   refused by its type, which is checked before the file is opened and again on the open
//!   handle. Files are opened non-blocking, so a FIFO that appears between the two checks
//!   cannot hang the read either.
//! - Every read has a size cap, checked on the file's length before reading, and enforced
//!   while reading (a file that grows is cut off and refused).
//! - A file named *inside* another file (a glTF buffer or image URI, a material's texture)
//!   is resolved with [`resolve_inside`]: a relative path without `..`, which after following
//!   symbolic links still lies inside the naming file's directory.

use std::io::Read;
use std::path::{Component, Path, PathBuf};

use crate::error::{Error, Result};

/// Largest file read as a glTF scene or buffer: 512 MiB (the largest model we ship is a few
/// MB; this only stops runaway reads).
pub const MAX_SCENE_BYTES: u64 = 512 << 20;

/// Largest image file read (painting, texture): 256 MiB. Image *dimensions* are checked
/// separately, from the header, before decoding ([`crate::images`]).
pub const MAX_IMAGE_BYTES: u64 = 256 << 20;

/// What kind of file `meta` describes, for messages.
fn kind_name(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// Refuses anything but a regular file (after symbolic links) of at most `cap` bytes.
pub fn check_regular(path: &Path, cap: u64) -> Result<u64> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    check_meta(path, &meta, cap)
}

fn check_meta(path: &Path, meta: &std::fs::Metadata, cap: u64) -> Result<u64> {
    if !meta.is_file() {
        return Err(Error::format(path, format!("is {}; only regular files are read", kind_name(meta))));
    }
    if meta.len() > cap {
        return Err(too_large(path, cap));
    }
    Ok(meta.len())
}

fn too_large(path: &Path, cap: u64) -> Error {
    let size = if cap >= 1 << 20 { format!("{} MiB", cap >> 20) } else { format!("{cap} bytes") };
    Error::format(path, format!("larger than the {size} this tool reads from one file"))
}

/// The bytes of the regular file `path`, at most `cap` of them (module docs).
pub fn read_regular(path: &Path, cap: u64) -> Result<Vec<u8>> {
    let (file, len) = open_regular(path, cap)?;
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(cap + 1).read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > cap {
        return Err(too_large(path, cap));
    }
    Ok(bytes)
}

/// The regular file `path`, opened for reading, and its length, at most `cap` (module
/// docs). For reading a header without the rest; a reader must still stop at `cap`.
pub fn open_regular(path: &Path, cap: u64) -> Result<(std::fs::File, u64)> {
    check_regular(path, cap)?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Non-blocking: opening a FIFO for reading would otherwise wait for a writer.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| Error::io(path, e))?;
    // The same checks on the handle: the path may have been replaced since.
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    let len = check_meta(path, &meta, cap)?;
    Ok((file, len))
}

/// Why [`resolve_inside`] refused a name.
#[derive(Debug)]
pub enum Refused {
    /// The file does not exist (or cannot be reached).
    Missing(PathBuf, std::io::Error),
    /// The name leads outside the directory (the reason, one line).
    Outside(String),
}

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refused::Missing(path, e) => write!(f, "missing file {}: {e}", path.display()),
            Refused::Outside(reason) => f.write_str(reason),
        }
    }
}

/// The file `name` (already percent-decoded) inside directory `dir`, checked to stay there:
/// not absolute, no `..`, and inside `dir` after following symbolic links.
pub fn resolve_inside(dir: &Path, name: &str) -> std::result::Result<PathBuf, Refused> {
    resolve(dir, name).map_err(|r| match r {
        Ok(missing) => missing,
        Err(reason) => Refused::Outside(reason),
    })
}

fn resolve(dir: &Path, name: &str) -> std::result::Result<PathBuf, std::result::Result<Refused, String>> {
    let rel = Path::new(name);
    if name.is_empty() {
        return Err(Err("an empty file name".into()));
    }
    if rel.is_absolute() || rel.has_root() {
        return Err(Err(format!("'{name}' is an absolute path; only files in its directory are read")));
    }
    if rel.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir)) {
        return Err(Err(format!("'{name}' leads out of its directory (..); only files in its directory are read")));
    }
    let joined = dir.join(rel);
    let real = std::fs::canonicalize(&joined).map_err(|e| Ok(Refused::Missing(joined.clone(), e)))?;
    let real_dir = std::fs::canonicalize(dir).map_err(|e| Ok(Refused::Missing(dir.to_path_buf(), e)))?;
    if !real.starts_with(&real_dir) {
        return Err(Err(format!(
            "'{name}' is a symbolic link to {}, outside its directory; only files in its directory are read",
            real.display()
        )));
    }
    Ok(joined)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_inside_are_read() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("scene");
        std::fs::create_dir(&dir).unwrap();
        std::fs::write(dir.join("a.bin"), b"abc").unwrap();
        std::fs::write(root.path().join("outside.bin"), b"secret").unwrap();
        assert_eq!(resolve_inside(&dir, "a.bin").unwrap(), dir.join("a.bin"));
        assert_eq!(resolve_inside(&dir, "./a.bin").unwrap(), dir.join("./a.bin"));
        assert!(resolve_inside(&dir, "../outside.bin").unwrap_err().to_string().contains("(..)"));
        let abs = root.path().join("outside.bin");
        assert!(resolve_inside(&dir, abs.to_str().unwrap()).unwrap_err().to_string().contains("absolute"));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&abs, dir.join("link.bin")).unwrap();
            assert!(resolve_inside(&dir, "link.bin").unwrap_err().to_string().contains("symbolic link"));
            std::os::unix::fs::symlink("a.bin", dir.join("inner.bin")).unwrap();
            assert!(resolve_inside(&dir, "inner.bin").is_ok(), "a link inside the directory is fine");
        }
        assert_eq!(read_regular(&dir.join("a.bin"), 3).unwrap(), b"abc");
        assert!(read_regular(&dir.join("a.bin"), 2).unwrap_err().to_string().contains("larger than"));
        let e = read_regular(&dir, 10).unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        #[cfg(target_os = "linux")]
        {
            let e = read_regular(Path::new("/dev/zero"), 10).unwrap_err().to_string();
            assert!(e.contains("/dev/zero: is a device"), "{e}");
        }
    }
}
