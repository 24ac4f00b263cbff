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
