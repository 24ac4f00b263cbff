//! The full fit of the live paintings: what `brdfpaint fit` makes of them (the reading, the
//! base, the notes: [`crate::pipeline::Loaded::read_and_fit`]), run on a worker thread once the
//! strokes pause, and shown only while the paintings are still the ones it read.
//!
//! ```text
//! strokes ─► instant refit (prepared system) ─► frame
//!    │ pause of PAUSE
//!    ▼
//! snapshot (stamp, paintings, G-buffers) ─► worker: read ─► fit ─► (stamp, material, notes)
//!                                                                     │ stamp still current?
//!                                                                     ▼ yes: shown; no: dropped
//! ```
//!
//! A [`Stamp`] names the state of the paintings a fit is of: the session's epoch (views and
//! settings) and every canvas's version. A stroke while the worker runs moves the stamp, so its
//! result is dropped when it lands, never shown; the next pause starts another. At most one
//! worker runs: a stale one is left to finish (the reading has no point to stop at) and its
//! result dropped. A session dropped mid-fit drops the receiver; the worker's send then fails
//! and its result goes with it.

use std::sync::mpsc;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::view::PaintView;
use crate::error::{Error, Result};
use crate::images::Painting;
use crate::material::Material;
use crate::note::Note;
use crate::pipeline::{Loaded, Options};
use crate::read::lobe::BaseChoice;
use crate::read::Reading;
use crate::render::GBuffer;
use crate::sample::{page, scene::geometry_from_gbuffer, Erosion, PaintedView};
use crate::scene::Light;

/// How long the strokes pause before the full fit starts: longer than the pen lift between
/// the strokes of one gesture (a few hundred ms), short enough to follow a pause a painter notices.
pub const PAUSE: Duration = Duration::from_millis(400);

/// The state of the paintings a fit is of: the session's epoch (views, settings, mapping)
/// and each canvas's version.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Stamp {
    pub epoch: u64,
    pub versions: Vec<u64>,
}

/// A full fit that landed: the material `brdfpaint fit` writes for these paintings and its
/// notes (load, reading, fit, in that order).
#[derive(Clone, Debug)]
pub struct FullFit {
    pub stamp: Stamp,
    pub material: Material,
    pub notes: Vec<Note>,
}

/// What a view gives the worker: everything `fit` loads from a scene and a painting file.
struct Snapshot {
    name: String,
    gbuffer: Arc<GBuffer>,
    light: Light,
    has_uv: bool,
    hit: Vec<bool>,
    lines: Vec<bool>,
    painting: Painting,
}

impl Snapshot {
    fn of(view: &PaintView) -> Snapshot {
        Snapshot {
            name: view.name.clone(),
            gbuffer: Arc::clone(&view.gbuffer),
            light: view.scene.light,
            has_uv: view.has_uv,
            hit: view.hit.clone(),
            lines: view.lines.clone(),
            painting: view.canvas.painting().clone(),
        }
    }

    /// The view as `brdfpaint fit --scene --image` loads it ([`crate::pipeline::load_views`]): the
    /// geometry of its G-buffer under the scene's light, eroded by `fit`'s default, and a
    /// painting made on the page without the page's own pixels.
    fn load(self, loaded: &mut Loaded) -> Result<()> {
        let Snapshot { name, gbuffer, light, has_uv, hit, lines, mut painting } = self;
        let geometry = geometry_from_gbuffer(&gbuffer, &light, has_uv, Erosion::default())?;
        if let Some(left) = page::remove_page(&mut painting, &lines, &hit) {
            loaded.notes.push(left.note(&name));
        }
        loaded.views.push(PaintedView { source: name.clone(), name, geometry, painting });
        loaded.gbuffers.push(GBuffer::clone(&gbuffer));
        Ok(())
    }
}

/// The options `brdfpaint fit` fits a scene's paintings with when given no flags, under the
/// session's factor settings and mapping: a mapping the painter chose is kept as `fit
/// --mapping` keeps it.
pub fn options(settings: &crate::factor::Settings, mapping: crate::factor::Mapping) -> Options {
    let keep_colours = mapping == crate::factor::Mapping::Auto;
    Options { settings: settings.clone(), mapping, base: BaseChoice::Auto, keep_colours, ..Options::default() }
}

/// Fits the snapshots as `brdfpaint fit` fits the same paintings: load, read, fit. Without
/// `fit`'s disk cache: every pause after new paint is a new pattern, and the cache would keep
/// a file for each.
fn run(views: Vec<Snapshot>, opts: &Options) -> Result<(Material, Vec<Note>)> {
    let mut loaded = Loaded { views: Vec::new(), gbuffers: Vec::new(), notes: Vec::new() };
    for v in views {
        v.load(&mut loaded)?;
    }
    let (_, fitted) = loaded.read_and_fit(&Reading::default(), opts, None)?;
    Ok((fitted.material, fitted.notes))
}

/// A worker thread's fit, of the paintings at `stamp`.
struct Running {
    stamp: Stamp,
    rx: mpsc::Receiver<Result<(Material, Vec<Note>)>>,
}

/// What a poll found.
#[derive(Debug)]
pub enum Landed {
    /// Nothing new.
    Nothing,
    /// A fit of the current paintings: show it.
    Current,
    /// A fit of paintings changed since: dropped.
    Stale,
}

/// The full fits of one session: the one running, the last one landed, and when the
/// paintings last changed.
#[derive(Default)]
pub struct FullFits {
    /// Off for sessions `fit` does not fit as scenes (a lit sphere's).
    pub off: bool,
    running: Option<Running>,
    landed: Option<FullFit>,
    /// The stamp of the last fit started or failed: not started again for the same paintings.
    tried: Option<Stamp>,
    /// The paintings' stamp when last seen and when it was first seen.
    seen: Option<(Stamp, Instant)>,
}

impl FullFits {
    /// The landed fit, when it is of the paintings at `stamp`.
    pub fn current(&self, stamp: &Stamp) -> Option<&FullFit> {
        self.landed.as_ref().filter(|f| &f.stamp == stamp)
    }

    /// Whether a fit runs on a worker.
    pub fn running(&self) -> bool {
        self.running.is_some()
    }

    /// Whether the paintings at `stamp` still wait for a fit (running, or due after a pause).
    pub fn owed(&self, stamp: &Stamp) -> bool {
        !self.off && (self.running.is_some() || self.tried.as_ref() != Some(stamp))
    }

    /// Notes that the paintings are at `stamp` at `now`: a change restarts the pause.
    pub fn observe(&mut self, stamp: &Stamp, now: Instant) {
        if self.seen.as_ref().is_none_or(|(s, _)| s != stamp) {
            self.seen = Some((stamp.clone(), now));
        }
    }

    /// Whether a fit of the paintings at `stamp` should start at `now`: none runs, none was
    /// tried for them, and they have not changed for [`PAUSE`].
    pub fn due(&self, stamp: &Stamp, now: Instant) -> bool {
        let paused = self.seen.as_ref().is_some_and(|(s, at)| s == stamp && now.duration_since(*at) >= PAUSE);
        !self.off && self.running.is_none() && self.tried.as_ref() != Some(stamp) && paused
    }

    /// Starts a fit of `views` (the paintings at `stamp`) on a worker thread. Does nothing
    /// while one runs (its result is taken or dropped first).
    pub fn start(&mut self, stamp: Stamp, views: &[PaintView], opts: Options) {
        if self.running.is_some() {
            return;
        }
        let snapshots: Vec<Snapshot> = views.iter().map(Snapshot::of).collect();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            // A dropped receiver (the session is gone) discards the result.
            let _ = tx.send(run(snapshots, &opts));
        });
        self.tried = Some(stamp.clone());
        self.running = Some(Running { stamp, rx });
    }

    /// Takes a finished fit: kept when it is of the paintings at `stamp`, dropped otherwise.
    /// `block` waits for a running one. Errors: the fit failed, or its thread stopped
    /// without a result (the last fit shown stays).
    pub fn take(&mut self, stamp: &Stamp, block: bool) -> Result<Landed> {
        let Some(running) = self.running.as_ref() else { return Ok(Landed::Nothing) };
        let result = match block {
            true => running.rx.recv().map_err(|_| mpsc::TryRecvError::Disconnected),
            false => running.rx.try_recv(),
        };
        let result = match result {
            Ok(r) => r,
            Err(mpsc::TryRecvError::Empty) => return Ok(Landed::Nothing),
            Err(mpsc::TryRecvError::Disconnected) => {
                self.running = None;
                return Err(Error::Numeric("the full fit's thread stopped without a result".into()));
            }
        };
        let fit_stamp = self.running.take().map(|r| r.stamp).unwrap_or_default();
        if &fit_stamp != stamp {
            return Ok(Landed::Stale);
        }
        let (material, notes) = result?;
        self.landed = Some(FullFit { stamp: fit_stamp, material, notes });
        Ok(Landed::Current)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stamp(epoch: u64, versions: &[u64]) -> Stamp {
        Stamp { epoch, versions: versions.to_vec() }
    }

    #[test]
    fn a_fit_is_due_only_after_a_pause_and_once_per_stamp() {
        let mut f = FullFits::default();
        let t0 = Instant::now();
        let s = stamp(0, &[3]);
        f.observe(&s, t0);
        assert!(!f.due(&s, t0 + PAUSE / 2), "no pause yet");
        assert!(f.due(&s, t0 + PAUSE), "paused");
        // A stroke restarts the pause.
        let s2 = stamp(0, &[4]);
        f.observe(&s2, t0 + PAUSE);
        assert!(!f.due(&s2, t0 + PAUSE + PAUSE / 2));
        assert!(f.due(&s2, t0 + 2 * PAUSE));
        // Tried once: not again for the same paintings.
        f.tried = Some(s2.clone());
        assert!(!f.due(&s2, t0 + 3 * PAUSE) && !f.owed(&s2));
        f.off = true;
        assert!(!f.due(&s, t0 + 3 * PAUSE) && !f.owed(&s));
    }

    #[test]
    fn a_stale_result_is_dropped_and_a_failure_reported() {
        let mut f = FullFits::default();
        let (tx, rx) = mpsc::channel();
        f.running = Some(Running { stamp: stamp(0, &[1]), rx });
        assert!(matches!(f.take(&stamp(0, &[1]), false), Ok(Landed::Nothing)));
        tx.send(Err(Error::input("nothing"))).unwrap();
        assert!(matches!(f.take(&stamp(0, &[2]), false), Ok(Landed::Stale)), "a stroke since: dropped, even an error");
        assert!(f.landed.is_none() && !f.running());
        let (tx, rx) = mpsc::channel();
        f.running = Some(Running { stamp: stamp(0, &[2]), rx });
        tx.send(Err(Error::input("nothing is painted"))).unwrap();
        let e = f.take(&stamp(0, &[2]), true).unwrap_err();
        assert!(e.to_string().contains("nothing is painted"), "{e}");
        // A worker gone without a result (dropped sender) is an error, not a hang.
        let (tx, rx) = mpsc::channel::<Result<(Material, Vec<Note>)>>();
        f.running = Some(Running { stamp: stamp(0, &[2]), rx });
        drop(tx);
        assert!(f.take(&stamp(0, &[2]), true).is_err() && !f.running());
    }
}
