//! Small helpers shared by several modules.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};

/// FNV-1a, 64 bit: a stable hash for cache keys and checksums (std's hasher is not stable
/// across releases, and these values are stored in files).
#[derive(Clone, Copy, Debug)]
pub struct Fnv(u64);

impl Fnv {
    pub fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl Default for Fnv {
    fn default() -> Self {
        Self::new()
    }
}

/// Write a file atomically: the bytes go to a temporary file beside `path`, which is then
/// renamed over it, so a reader never sees a half-written file.
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

/// A unique temporary path in the same directory as `path` (same file system, so rename is
/// atomic).
pub fn temp_sibling(path: &Path) -> std::path::PathBuf {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let name = path.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()))
}

/// Whether progress bars should be drawn: only when stderr is a terminal.
pub fn progress_enabled() -> bool {
    use std::io::IsTerminal;
    std::io::stderr().is_terminal()
}

/// Clear the upper halves of the vector registers.
///
/// faer's AVX-512 matrix kernels return with the upper register state dirty. Until it is
/// cleared, every legacy-SSE instruction that follows pays a transition penalty: measured
/// here, `f64::exp` went from 4 ns to 130 ns per call after one small matrix product,
/// which made a 0.1 ms refit take 0.3 ms. Call this after a faer kernel on a hot path.
#[inline]
pub fn clear_upper_vector_state() {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU supports AVX, checked just above.
        unsafe { zeroupper() }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn zeroupper() {
    std::arch::x86_64::_mm256_zeroupper();
}

/// Whether an output directory's path is free to write: nothing there or an empty directory
/// (`true`), or a directory holding files (`false`, the caller decides whether they are its
/// own). Anything else there, a file or a link, is refused with one line.
pub fn output_dir_is_fresh(dir: &Path) -> Result<bool> {
    let meta = match std::fs::symlink_metadata(dir) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(true),
        Err(e) => return Err(Error::io(dir, e)),
    };
    if !meta.is_dir() {
        return Err(Error::input(format!("{} exists and is not a directory; not overwriting it", dir.display())));
    }
    Ok(std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?.next().is_none())
}

/// Puts the finished directory `tmp` (a sibling) at `dir`, which is missing or empty
/// (checked by the caller): rename cannot replace a directory everywhere, so an empty one is
/// removed first.
pub fn move_into_fresh(tmp: &Path, dir: &Path) -> Result<()> {
    if dir.exists() {
        std::fs::remove_dir(dir).map_err(|e| Error::io(dir, e))?;
    }
    std::fs::rename(tmp, dir).map_err(|e| Error::io(dir, e))
}

/// Replace the directory `dir` by the finished directory `tmp` (a sibling, same file
/// system): `dir` is moved aside, `tmp` renamed into place, and the old one removed; if the
/// second rename fails, `dir` is put back. A missing `dir` is simply created by the rename.
pub fn swap_dir(tmp: &Path, dir: &Path) -> Result<()> {
    if !dir.exists() {
        return std::fs::rename(tmp, dir).map_err(|e| Error::io(dir, e));
    }
    let old = temp_sibling(dir);
    std::fs::rename(dir, &old).map_err(|e| Error::io(dir, e))?;
    if let Err(e) = std::fs::rename(tmp, dir) {
        let _ = std::fs::rename(&old, dir);
        return Err(Error::io(dir, e));
    }
    let _ = std::fs::remove_dir_all(&old);
    Ok(())
}
