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
//! with it and the prepared system must be prepared again (thesis 3.2.2: the system depends
//! on where the samples are). That runs on the session's background thread, as a stroke
//! that paints new pixels does: [`SphereSession::set_light`] only records the light asked
//! for, and [`SphereSession::update`] renders the view under it once no prepare is running
//! and the last one has been solved. A drag that moves the light every frame thus refits as
//! fast as prepares finish, always towards the latest light, with one prepare at a time.

use std::path::Path;

use glam::DVec3;

use super::canvas::Canvas;
use super::session::PaintSession;
use super::view::PaintView;
use crate::error::{Error, Result};
use crate::litsphere::{self, LightEstimate, Picture};
use crate::render::Renderer;

/// What the session's view of a lit sphere is called.
pub const VIEW_NAME: &str = "lit sphere";

/// A lit-sphere picture, its estimated light and the light its view is lit by now.
#[derive(Clone, Debug)]
pub struct SphereSession {
    /// The picture as `fit --lit-sphere` reads it.
    pub picture: Picture,
    /// The light estimated from the picture's shading (`None` when it was given).
    pub estimate: Option<LightEstimate>,
    /// The light of the view in the paint session (towards the light, picture frame: x
    /// right, y up, z to the viewer).
    light: DVec3,
    /// A light asked for and not yet applied.
    wanted: Option<DVec3>,
}

impl SphereSession {
    /// Reads the picture at `path` and estimates its light, or takes `light`. No GL: it may
    /// run on any thread. Errors, one line each: the picture's, or `light` is not a direction.
    pub fn open(path: &Path, light: Option<DVec3>) -> Result<SphereSession> {
        SphereSession::from_picture(Picture::read(path, litsphere::MAX_SIDE)?, light)
    }

    /// [`SphereSession::open`] of a picture already read.
    pub fn from_picture(picture: Picture, light: Option<DVec3>) -> Result<SphereSession> {
        let (light, estimate) = match light {
            Some(l) => (litsphere::direction(l)?, None),
            None => {
                let e = picture.estimate_light()?;
                (e.direction, Some(e))
            }
        };
        Ok(SphereSession { picture, estimate, light, wanted: None })
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
    /// settings and mapping are kept); the view's index.
    pub fn start(&self, renderer: &mut Renderer, session: &mut PaintSession) -> Result<usize> {
        let view = self.view(renderer, self.light)?;
        *session = PaintSession::new(session.settings().clone(), session.mapping());
        Ok(session.add_view(view))
    }

    /// Asks for the light `light` (applied by [`SphereSession::update`]). Errors: not a
    /// direction.
    pub fn set_light(&mut self, light: DVec3) -> Result<()> {
        let l = litsphere::direction(light)?;
        self.wanted = (l != self.light).then_some(l);
        Ok(())
    }

    /// Applies the light asked for to view `k` of `session` when no prepare is running there
    /// (`solved`: the last prepared system has been solved, so its fit is not thrown away):
    /// the view is rendered under the new light, keeping its canvas (the picture and any
    /// strokes over it, with their undo history), and the session prepares it in the
    /// background at its next refit. Returns whether the light was applied.
    pub fn update(&mut self, renderer: &mut Renderer, session: &mut PaintSession, k: usize, solved: bool) -> Result<bool> {
        if self.wanted.is_none() || session.preparing() || !solved {
            return Ok(false);
        }
        self.apply(renderer, session, k)?;
        Ok(true)
    }

    /// Renders view `k` under the light asked for, keeping its canvas.
    fn apply(&mut self, renderer: &mut Renderer, session: &mut PaintSession, k: usize) -> Result<()> {
        let Some(light) = self.wanted else { return Ok(()) };
        let current = session.views.get_mut(k).ok_or_else(|| Error::input(format!("no view {k} to light")))?;
        let mut view = PaintView::new(renderer, VIEW_NAME, self.picture.scene(light), current.width, current.height)?;
        std::mem::swap(&mut view.canvas, &mut current.canvas);
        // The old view's prepare (if one runs) is dropped with it: its result is for the old light.
        session.replace_view(k, view);
        self.light = light;
        self.wanted = None;
        Ok(())
    }

    /// Applies the light asked for and waits for the fit under it: where a drag that ends
    /// arrives, in one call (tests and scripts). The fit is `fit --lit-sphere --light` of the
    /// picture (with any strokes painted over it).
    pub fn settle(&mut self, renderer: &mut Renderer, session: &mut PaintSession, k: usize) -> Result<super::Refit> {
        self.apply(renderer, session, k)?;
        session.settle()
    }
}
