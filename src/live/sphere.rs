//! A lit sphere or MatCap as the one view of a [`PaintSession`], with a light the user can
//! move: what the viewer opens when a picture of a sphere is dropped on it.
//!
//! The picture, its disk and its estimated light are [`crate::litsphere`]'s, exactly as
//! `brdfpaint fit --lit-sphere` takes them; the view is that command's scene rendered as a
//! [`PaintView`], with the picture on its canvas. So the session's settled fit is the
//! command's material (tests/lit_sphere.rs checks it), and painting over the sphere works
//! as on any view.
//!
//! **Moving the light.** The light is part of the scene, so every sample's query moves
//! with it: the view is rendered again under the new light and the prepared system prepared
//! again (thesis 3.2.2: the system depends on where the samples are). Neither stalls the
//! caller: the view is rendered by a thread of its own (its own headless GL context), and
//! the prepare runs on the session's background thread, as for a stroke that paints new
//! pixels. [`SphereSession::set_light`] only records the light asked for;
//! [`SphereSession::update`], called every frame, passes it to the render thread, and puts
//! a rendered view in place once no prepare is running and the last one has been solved. A
//! drag that moves the light every frame thus refits as fast as prepares finish, always
//! towards the latest light, one render and one prepare at a time.

use std::path::Path;
use std::sync::mpsc;

use glam::DVec3;

use super::canvas::Canvas;
use super::session::PaintSession;
use super::view::PaintView;
use crate::error::{Error, Result};
use crate::gl::HeadlessContext;
use crate::factor::{Channels, Mapping, Settings};
use crate::images::palette::Palette;
use crate::litsphere::{self, LightEstimate, Picture, Stylization};
use crate::render::Renderer;

/// What the session's view of a lit sphere is called.
pub const VIEW_NAME: &str = "lit sphere";

/// A lit-sphere picture, its estimated light and the light its view is lit by now.
pub struct SphereSession {
    /// The picture as `fit --lit-sphere` reads it.
    pub picture: Picture,
    /// The light estimated from the picture's shading (`None` when it was given).
    pub estimate: Option<LightEstimate>,
    /// Physical or stylized, as `fit --lit-sphere --style auto` decides.
    pub stylization: Stylization,
    /// The light of the view in the paint session (towards the light, picture frame: x
    /// right, y up, z to the viewer).
    light: DVec3,
    /// A light asked for and not yet applied.
    wanted: Option<DVec3>,
    /// The render thread, started at the first light asked for (`None` before, or where no
    /// second GL context can be had: then views are rendered on the caller's).
    lighting: Option<Lighting>,
    /// Whether the render thread was tried (it is not tried again).
    lighting_tried: bool,
    /// The light of the view being rendered, and a rendered view waiting to be put in place.
    rendering: Option<DVec3>,
    ready: Option<(DVec3, PaintView)>,
}

/// A thread with a GL context of its own that renders the picture's view under the lights
/// it is sent.
struct Lighting {
    /// `None` only while dropping: the thread ends when this sender is gone.
    requests: Option<mpsc::Sender<DVec3>>,
    views: mpsc::Receiver<Result<(DVec3, PaintView)>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Drop for Lighting {
    /// Ends the thread and waits for it (at most the one render under way). A thread left
    /// to end by itself could still be destroying its GL context while the process exits
    /// and Mesa's exit handlers free what it uses: heap corruption at exit, seen as an
    /// abort after every test had passed (`viewer_ui`, about one run in 15).
    fn drop(&mut self) {
        self.requests = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl Lighting {
    fn start(picture: &Picture) -> Option<Lighting> {
        let (requests, inbox) = mpsc::channel::<DVec3>();
        let (outbox, views) = mpsc::channel();
        let (disk, w, h) = (picture.disk, picture.painting.width, picture.painting.height);
        let (started_tx, started) = mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("lit sphere views".into())
            .spawn(move || {
                let gl = HeadlessContext::new().and_then(|ctx| Renderer::new(ctx.gl()).map(|r| (ctx, r)));
                let Ok((_ctx, mut renderer)) = gl else {
                    let _ = started_tx.send(false);
                    return;
                };
                let _ = started_tx.send(true);
                // Ends when the session (the sender) is dropped.
                while let Ok(light) = inbox.recv() {
                    let view = PaintView::new(&mut renderer, VIEW_NAME, litsphere::scene(&disk, w, h, light), w, h);
                    if outbox.send(view.map(|v| (light, v))).is_err() {
                        return;
                    }
                }
            })
            .ok()?;
        let lighting = Lighting { requests: Some(requests), views, thread: Some(thread) };
        // A thread that could not make its context has ended; dropping joins it.
        started.recv().ok().filter(|&ok| ok).map(|_| lighting)
    }
}

impl SphereSession {
    /// Reads the picture at `path` and estimates its light, or takes `light`. No GL: it may
    /// run on any thread. Errors, one line each: the picture's, or `light` is not a direction.
    pub fn open(path: &Path, light: Option<DVec3>) -> Result<SphereSession> {
        SphereSession::from_picture(Picture::read(path, litsphere::MAX_SIDE)?, light)
    }

    /// [`SphereSession::open`] of a picture already read.
    pub fn from_picture(picture: Picture, light: Option<DVec3>) -> Result<SphereSession> {
        // Read as `fit --lit-sphere` reads it by default (`--style auto`).
        let stylization = Stylization::decide(litsphere::Style::Auto, &picture);
        let (light, estimate) = match light {
            Some(l) => (litsphere::direction(l)?, None),
            None => {
                let e = stylization.estimate_light(&picture)?;
                (e.direction, Some(e))
            }
        };
        Ok(SphereSession { picture, estimate, stylization, light, wanted: None, lighting: None, lighting_tried: false, rendering: None, ready: None })
    }

    /// The fit settings of this picture under its applied light from the user's `base`
    /// ([`Stylization::settings`]).
    pub fn settings(&self, base: &Settings) -> Settings {
        self.stylization.settings(base, &self.picture, self.light, false, false)
    }

    /// A paint session for this picture: `base`'s settings as [`SphereSession::settings`]
    /// makes them, the robust solve of a stylized picture, and `mapping`.
    pub fn paint_session(&self, base: &Settings, mapping: Mapping) -> PaintSession {
        let mut session = PaintSession::new(self.settings(base), mapping);
        session.set_robust(self.stylization.robust());
        session
    }

    /// The light the fit is for, or will be once the light asked for is applied: what a
    /// light gizmo shows.
    pub fn light(&self) -> DVec3 {
        self.wanted.unwrap_or(self.light)
    }

    /// The light of the view in the paint session now.
    pub fn applied_light(&self) -> DVec3 {
        self.light
    }

    /// Whether a light was asked for and not yet applied.
    pub fn waiting(&self) -> bool {
        self.wanted.is_some()
    }

    /// The picture's view lit from `light`, with the picture on its canvas.
    pub fn view(&self, renderer: &mut Renderer, light: DVec3) -> Result<PaintView> {
        let p = &self.picture.painting;
        let mut view = PaintView::new(renderer, VIEW_NAME, self.picture.scene(light), p.width, p.height)?;
        view.canvas = Canvas::from_painting(p.clone());
        Ok(view)
    }

    /// Starts `session` over with this picture's view as its only view (the session's
    /// settings and mapping, as [`SphereSession::paint_session`] makes them); the view's
    /// index.
    pub fn start(&self, renderer: &mut Renderer, session: &mut PaintSession) -> Result<usize> {
        let view = self.view(renderer, self.light)?;
        *session = self.paint_session(session.settings(), session.mapping());
        Ok(session.add_view(view))
    }

    /// Asks for the light `light` (applied by [`SphereSession::update`]). Errors: not a
    /// direction.
    pub fn set_light(&mut self, light: DVec3) -> Result<()> {
        let l = litsphere::direction(light)?;
        self.wanted = (l != self.light).then_some(l);
        Ok(())
    }

    /// Moves the light asked for along, without waiting: sends it to the render thread when
    /// that is free, and puts the last rendered view in place of view `k` of `session` when
    /// no prepare runs there and `solved` (the last prepared system has been solved, so its
    /// fit is not thrown away). The new view keeps the canvas (the picture and any strokes
    /// over it, with their undo history); the session prepares it at its next refit. Returns
    /// whether a view was put in place. Without a render thread the view is rendered here.
    pub fn update(&mut self, renderer: &mut Renderer, session: &mut PaintSession, k: usize, solved: bool) -> Result<bool> {
        if self.wanted.is_some() && !self.lighting_tried {
            self.lighting_tried = true;
            self.lighting = Lighting::start(&self.picture);
        }
        if let (Some(lighting), Some(_)) = (&self.lighting, self.rendering) {
            match lighting.views.try_recv() {
                Ok(view) => {
                    self.rendering = None;
                    // Nearer the light asked for than the view's; stale once none is asked.
                    self.ready = Some(view?).filter(|_| self.wanted.is_some());
                }
                Err(mpsc::TryRecvError::Empty) => {}
                Err(mpsc::TryRecvError::Disconnected) => {
                    self.lighting = None;
                    self.rendering = None;
                }
            }
        }
        // The latest light asked for goes to the render thread once it is free.
        if let (Some(lighting), Some(light), None) = (&self.lighting, self.wanted, self.rendering) {
            let send = |r: &mpsc::Sender<DVec3>| r.send(light).is_ok();
            if self.ready.as_ref().is_none_or(|r| r.0 != light) && lighting.requests.as_ref().is_some_and(send) {
                self.rendering = Some(light);
            }
        }
        if session.preparing() || !solved {
            return Ok(false);
        }
        let view = match self.ready.take() {
            Some(v) => v,
            None if self.lighting.is_none() && self.wanted.is_some() => {
                let light = self.wanted.expect("checked");
                (light, self.render(renderer, session, k, light)?)
            }
            None => return Ok(false),
        };
        self.install(session, k, view)?;
        Ok(true)
    }

    /// View `k` rendered again under `light` on the caller's GL context, with an empty canvas.
    fn render(&self, renderer: &mut Renderer, session: &PaintSession, k: usize, light: DVec3) -> Result<PaintView> {
        let current = session.views.get(k).ok_or_else(|| Error::input(format!("no view {k} to light")))?;
        PaintView::new(renderer, VIEW_NAME, self.picture.scene(light), current.width, current.height)
    }

    /// Puts `view` (lit from `light`) in place of view `k`, with view `k`'s canvas.
    fn install(&mut self, session: &mut PaintSession, k: usize, (light, mut view): (DVec3, PaintView)) -> Result<()> {
        let current = session.views.get_mut(k).ok_or_else(|| Error::input(format!("no view {k} to light")))?;
        std::mem::swap(&mut view.canvas, &mut current.canvas);
        // The old view's prepare (if one runs) is dropped with it: its result is for the old light.
        session.replace_view(k, view);
        self.light = light;
        // The light prior's floor and key light follow the light, as `fit --light` sets them
        // (Stylization::settings); the new view is prepared again anyway.
        if !self.stylization.stylized {
            session.set_settings(self.settings(session.settings()))?;
        }
        if self.wanted == Some(light) {
            self.wanted = None;
        }
        Ok(())
    }

    /// Puts the view under the light asked for in place and waits for the fit under it:
    /// where a drag that ends arrives, in one call (tests and scripts). The fit is `fit
    /// --lit-sphere --light` of the picture (with any strokes painted over it).
    pub fn settle(&mut self, renderer: &mut Renderer, session: &mut PaintSession, k: usize) -> Result<super::Refit> {
        if let Some(light) = self.wanted {
            let view = match self.ready.take() {
                Some(v) if v.0 == light => v,
                _ => (light, self.render(renderer, session, k, light)?),
            };
            self.install(session, k, view)?;
        }
        self.settle_colours(session)
    }

    /// [`PaintSession::settle`] as `fit --lit-sphere` fits ([`litsphere::colours::fit`]): the
    /// thesis's fit, and while the fit invents colours each of [`litsphere::colours::TRIES`]
    /// in turn, the first that does not (else the one that invents least) left in place. A
    /// mapping the painter chose is kept, as `fit --mapping` keeps it.
    fn settle_colours(&self, session: &mut PaintSession) -> Result<super::Refit> {
        let thesis = (Channels::Independent, Mapping::Auto);
        let current = (session.settings().channels, session.mapping());
        if !(current == thesis || litsphere::colours::TRIES.contains(&current)) {
            return session.settle();
        }
        let set = |session: &mut PaintSession, (channels, mapping): (Channels, Mapping)| -> Result<()> {
            session.set_settings(Settings { channels, ..session.settings().clone() })?;
            session.set_mapping(mapping);
            Ok(())
        };
        set(session, thesis)?;
        let mut refit = session.settle()?;
        let palette = Palette::of_painting(&self.picture.painting);
        let invented = |session: &PaintSession| session.live_material().map_or(0.0, |m| litsphere::colours::invented(m, &palette));
        let first = invented(session);
        let mut tried = None;
        let chosen = litsphere::colours::choose(first, |channels, mapping| {
            set(session, (channels, mapping))?;
            refit = session.settle()?;
            tried = Some((channels, mapping));
            Ok(invented(session))
        })?;
        let keep = chosen.map_or(thesis, |c| litsphere::colours::TRIES[c.index]);
        if tried.is_none_or(|t| t == keep) {
            return Ok(refit);
        }
        set(session, keep)?;
        session.settle()
    }
}
