//! Notes: one-line remarks on input that was read, but perhaps not as its author expects (a
//! scene with two cameras is seen through the first). The library has no terminal of its
//! own: a program that wants them installs a handler ([`set_handler`]); `brdfpaint` prints
//! them on stderr as `note: …`. Without a handler they are dropped.

use std::sync::OnceLock;

static HANDLER: OnceLock<fn(&str)> = OnceLock::new();

/// Sends every later note to `handler` (once per process; a second call is ignored).
pub fn set_handler(handler: fn(&str)) {
    let _ = HANDLER.set(handler);
}

/// Passes `text`, made one line ([`crate::error::one_line`]), to the handler, if any.
pub(crate) fn note(text: &str) {
    if let Some(handler) = HANDLER.get() {
        handler(&crate::error::one_line(text));
    }
}
