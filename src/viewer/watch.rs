//! Watch mode: refit whenever another program rewrites a painting.
//!
//! The file is polled (modification time, size and a hash of its bytes; no platform
//! notification API, so it works the same on every file system, network ones included). A
//! painter that writes in place can be caught mid-write: then the file does not decode, the
//! last good painting stays, and [`Watcher::status`] says why. The next change is tried
//! again.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use super::canvas::Painting;
use super::paint::PaintSession;
use crate::error::Result;
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
    pub fn poll(&mut self, session: &mut PaintSession) -> Option<&WatchStatus> {
        if self.last_poll.is_some_and(|t| t.elapsed() < self.interval) {
            return None;
        }
        self.check(session)
    }

    /// Looks at the file now. When it changed since the last look: reads it, puts it on the
    /// view's canvas, and fits (waiting for the prepare: the fit is exact). Returns the new
    /// status when something happened, `None` when the file is unchanged.
    pub fn check(&mut self, session: &mut PaintSession) -> Option<&WatchStatus> {
        self.last_poll = Some(Instant::now());
        let meta = std::fs::metadata(&self.path);
        let bytes = match meta.as_ref().map_err(|e| e.to_string()).and_then(|_| std::fs::read(&self.path).map_err(|e| e.to_string())) {
            Ok(b) => b,
            Err(e) => {
                let msg = format!("{}: {e}", self.path.display());
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
        let stamp = (meta.ok().and_then(|m| m.modified().ok()), bytes.len() as u64, h.finish());
        if self.seen == Some(stamp) {
            return None;
        }
        self.seen = Some(stamp);
        self.status = match self.load(session, &bytes) {
            Ok(samples) => WatchStatus::Fitted { samples },
            Err(e) => WatchStatus::Failed(e.to_string()),
        };
        Some(&self.status)
    }

    fn load(&self, session: &mut PaintSession, bytes: &[u8]) -> Result<usize> {
        let view = &session.views[self.view];
        let painting = Painting::decode(&self.path, bytes)?;
        if painting.width != view.width || painting.height != view.height {
            return Err(crate::Error::format(
                &self.path,
                format!("the painting is {}x{} but the view is {}x{}", painting.width, painting.height, view.width, view.height),
            ));
        }
        let before = session.views[self.view].canvas.painting().clone();
        session.views[self.view].canvas.set_painting(&painting)?;
        match session.settle() {
            Ok(r) => Ok(r.samples),
            Err(e) => {
                // Keep the canvas consistent with the material that stays.
                let _ = session.views[self.view].canvas.set_painting(&before);
                Err(crate::Error::input(format!("{}: {e}", self.path.display())))
            }
        }
    }
}
