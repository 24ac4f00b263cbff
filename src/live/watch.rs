//! Watch mode: refit whenever another program rewrites a painting.
//!
//! The file is polled (modification time, size and a hash of its bytes; no platform
//! notification API, so it works the same on every file system, network ones included). It
//! is read as `brdfpaint fit` reads a painting: under the file-access policy
//! ([`crate::fsio`]) and through the one validated decoder ([`crate::images::Painting`]). A
//! painter that writes in place can be caught mid-write: then the file does not decode (a
//! JPEG cut short included), the last good painting and material stay, and
//! [`Watcher::status`] says why. The next change is tried again.
//!
//! A painting of another size than the view follows the size rule of `brdfpaint fit`
//! ([`super::view`]): of the camera's aspect within 1%, the view is rendered again at its size
//! (hence the [`Renderer`] these calls take); otherwise it is refused, naming both sizes.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use super::canvas::Painting;
use super::session::PaintSession;
use super::view::check_painting_size;
use crate::error::{Error, Result};
use crate::render::Renderer;
use crate::util::Fnv;

/// What the last look at the file found.
#[derive(Clone, Debug, PartialEq)]
pub enum WatchStatus {
    /// Nothing read yet.
    Waiting,
    /// The painting was read and fitted.
    Fitted { samples: usize },
    /// The file could not be used; the last good material stays. One line naming the file.
    Failed(String),
}

/// Polls one painting file for one view of a [`PaintSession`].
pub struct Watcher {
    path: PathBuf,
    view: usize,
    /// (modified, length, content hash) of the last version tried.
    seen: Option<(Option<SystemTime>, u64, u64)>,
    last_poll: Option<Instant>,
    /// Poll at most this often.
    pub interval: Duration,
    status: WatchStatus,
}

impl Watcher {
    /// Watches `path` as the painting of view `view`.
    pub fn new(path: impl Into<PathBuf>, view: usize) -> Watcher {
        Watcher {
            path: path.into(),
            view,
            seen: None,
            last_poll: None,
            interval: Duration::from_millis(200),
            status: WatchStatus::Waiting,
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn status(&self) -> &WatchStatus {
        &self.status
    }

    /// Polls if the interval has passed since the last poll; see [`Watcher::check`].
    pub fn poll(&mut self, session: &mut PaintSession, renderer: &mut Renderer) -> Option<&WatchStatus> {
        if self.last_poll.is_some_and(|t| t.elapsed() < self.interval) {
            return None;
        }
        self.check(session, renderer)
    }

    /// Looks at the file now. When it changed since the last look: reads it, puts it on the
    /// view's canvas (rendering the view again when the painting has another size of the
    /// camera's aspect), and fits (waiting for the prepare: the fit is exact). Returns the new
    /// status when something happened, `None` when the file is unchanged.
    pub fn check(&mut self, session: &mut PaintSession, renderer: &mut Renderer) -> Option<&WatchStatus> {
        self.last_poll = Some(Instant::now());
        let modified = std::fs::metadata(&self.path).ok().and_then(|m| m.modified().ok());
        // The same file-access policy and size cap as `fit` (a FIFO or a device put at the
        // path is refused by its type and never blocks the window's thread).
        let bytes = match crate::fsio::read_regular(&self.path, crate::fsio::MAX_IMAGE_BYTES) {
            Ok(b) => b,
            Err(e) => {
                let msg = e.to_string();
                if self.status == WatchStatus::Failed(msg.clone()) {
                    return None;
                }
                self.status = WatchStatus::Failed(msg);
                self.seen = None;
                return Some(&self.status);
            }
        };
        let mut h = Fnv::new();
        h.write(&bytes);
        let stamp = (modified, bytes.len() as u64, h.finish());
        if self.seen == Some(stamp) {
            return None;
        }
        self.seen = Some(stamp);
        self.status = match self.load(session, renderer, &bytes) {
            Ok(samples) => WatchStatus::Fitted { samples },
            Err(e) => WatchStatus::Failed(e.to_string()),
        };
        Some(&self.status)
    }

    fn load(&self, session: &mut PaintSession, renderer: &mut Renderer, bytes: &[u8]) -> Result<usize> {
        let Some(view) = session.views.get(self.view) else {
            return Err(Error::input(format!("{}: no view {} to paint", self.path.display(), self.view)));
        };
        // The validated decoder of every painting (`images::Painting`): a JPEG cut short or
        // with a damaged scan is an error here, not a grey painting fitted over a good one.
        let painting = Painting::decode(&self.path, bytes)?;
        let (w, h) = (painting.width, painting.height);
        check_painting_size(view, &self.path.display().to_string(), w, h)?;
        // Another size of the same aspect: the view at that size, the old one kept for a failure.
        let old_view = if (w, h) != (view.width, view.height) {
            let resized = view.resized(renderer, w, h)?;
            session.replace_view(self.view, resized)
        } else {
            None
        };
        let before = session.views[self.view].canvas.painting().clone();
        let result = session.views[self.view].canvas.set_painting(&painting).and_then(|()| session.settle());
        match result {
            Ok(r) => Ok(r.samples),
            Err(e) => {
                // Keep the view and canvas consistent with the material that stays.
                match old_view {
                    Some(old) => {
                        session.replace_view(self.view, old);
                    }
                    None => {
                        let _ = session.views[self.view].canvas.set_painting(&before);
                    }
                }
                Err(Error::input(format!("{}: {e}", self.path.display())))
            }
        }
    }
}
