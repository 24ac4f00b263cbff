//! The one error type of the library. Every failure a user can cause has a variant whose
//! message is one readable line naming the file (when there is one) and the reason.

use std::path::{Path, PathBuf};

/// Result alias used across the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong, one documented variant per kind of failure.
///
/// Its message is one line whatever a name in it holds: control characters (a newline in a
/// file or texture name) are written as escapes ([`one_line`]).
#[derive(Debug)]
pub enum Error {
    /// Reading or writing a file failed at the operating-system level.
    Io { path: PathBuf, source: std::io::Error },

    /// A file exists but its content is not what it claims to be (corrupt, truncated,
    /// unsupported version, wrong size).
    Format { path: PathBuf, reason: String },

    /// Input data that cannot be used: NaN or negative sample values, empty sample sets,
    /// mismatched sizes, absurd resolutions. The message names the offending value.
    Input(String),

    /// The numerical solve failed (e.g. the system is not positive definite).
    Numeric(String),

    /// OpenGL or EGL failed: no context, shader compile or link errors, framebuffer errors.
    Gl(String),
}

impl Error {
    /// The message before [`one_line`] escapes it.
    fn raw_message(&self) -> String {
        match self {
            Error::Io { path, source } => format!("{}: {source}", path.display()),
            Error::Format { path, reason } => format!("{}: {reason}", path.display()),
            Error::Input(reason) => reason.clone(),
            Error::Numeric(reason) => format!("numerical failure: {reason}"),
            Error::Gl(reason) => format!("OpenGL: {reason}"),
        }
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&one_line(&self.raw_message()))
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// `text` on one line: control characters (newline, tab, escape, ...) written as Rust
/// escapes (`\n`, `\t`, `\u{1b}`), everything else as it is. Errors and notes go through
/// it, so a name holding a newline cannot split a message or forge a second one.
pub fn one_line(text: &str) -> String {
    if !text.chars().any(char::is_control) {
        return text.to_string();
    }
    text.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_one_line_whatever_a_name_holds() {
        let e = Error::format("dir/a\nb.exr", "texture 'x\ty' is missing\r");
        assert_eq!(e.to_string(), "dir/a\\nb.exr: texture 'x\\ty' is missing\\r");
        assert_eq!(Error::input("bell \u{7} and escape \u{1b}[31m").to_string(), "bell \\u{7} and escape \\u{1b}[31m");
        assert_eq!(Error::input("plain é ünïcode").to_string(), "plain é ünïcode");
        let io = Error::io("x\ny", std::io::Error::from(std::io::ErrorKind::NotFound));
        assert!(!io.to_string().contains('\n') && std::error::Error::source(&io).is_some());
    }
}
