//! The one error type of the library. Every failure a user can cause has a variant whose
//! message is one readable line naming the file (when there is one) and the reason.

use std::path::{Path, PathBuf};

/// Result alias used across the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong, one documented variant per kind of failure.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or writing a file failed at the operating-system level.
    #[error("{}: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },

    /// A file exists but its content is not what it claims to be (corrupt, truncated,
    /// unsupported version, wrong size).
    #[error("{}: {reason}", path.display())]
    Format { path: PathBuf, reason: String },

    /// Input data that cannot be used: NaN or negative sample values, empty sample sets,
    /// mismatched sizes, absurd resolutions. The message names the offending value.
    #[error("{0}")]
    Input(String),

    /// The numerical solve failed (e.g. the system is not positive definite).
    #[error("numerical failure: {0}")]
    Numeric(String),

    /// OpenGL or EGL failed: no context, shader compile or link errors, framebuffer errors.
    #[error("OpenGL: {0}")]
    Gl(String),
}

impl Error {
    /// An [`Error::Io`] for `path`.
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Self {
        Error::Io { path: path.as_ref().to_path_buf(), source }
    }

    /// An [`Error::Format`] for `path`.
    pub fn format(path: impl AsRef<Path>, reason: impl Into<String>) -> Self {
        Error::Format { path: path.as_ref().to_path_buf(), reason: reason.into() }
    }

    /// An [`Error::Input`].
    pub fn input(reason: impl Into<String>) -> Self {
        Error::Input(reason.into())
    }
}

thread_local! {
    /// How many [`catch_panic`] calls are running on this thread.
    static CATCHING: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
}

/// Runs `f`, turning a panic inside it into `Err` with the panic's message. Only for code of
/// dependencies that may panic on malformed input (the glTF reader); our own code returns
/// errors instead.
pub(crate) fn catch_panic<T>(f: impl FnOnce() -> T) -> std::result::Result<T, String> {
    CATCHING.with(|c| c.set(c.get() + 1));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    CATCHING.with(|c| c.set(c.get() - 1));
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into())
    })
}

/// Whether a panic on this thread is being caught and turned into an [`Error`] by the
/// library: a panic hook stays quiet then (the error is reported as one line instead).
pub fn panic_is_caught() -> bool {
    CATCHING.with(|c| c.get() > 0)
}
