//! Reading paintings as evidence of a material: what the painter meant, told from what the
//! brush did (issue 11). The one home of reading painting(s) as evidence, between sampling
//! ([`crate::sample`]) and the fit ([`crate::pipeline::fit`]).
//!
//! A [`Reader`] estimates, in this order:
//! 1. **flat tones** ([`tones::smooth`]): a posterized painting becomes the smooth shading
//!    between its tones' edges, first, since every later step fits the painting and a
//!    staircase misleads it;
//! 2. **the painter's light** ([`register`]): each view's light turned to where the painting
//!    was shaded from; a toned painting's on its steps as painted, where that is clear
//!    ([`Pass::register_as_painted`]);
//! 3. **stray strokes** ([`strays`]): paint the shading around it does not explain, repainted
//!    with that shading, and the light searched again without them;
//! 4. **a toned view's light judged on its tones**, whose edges are where the painter put the
//!    shading ([`Pass::judge_toned_turns`]);
//! 5. **the tones read through the lobe family that holds them** ([`tones::refine`]).
//!
//! Strays found in flat tones are tones of their own (the interpolation between edges runs
//! to them), so there they are left out instead, and the paintings read again from the start
//! without them ([`Reader::read`]). Which lobe goes under the product is the fit's choice, on
//! the samples read here ([`lobe`]).

pub mod lobe;
pub mod proxy;
pub mod register;
pub mod strays;
pub mod tones;

use glam::DQuat;

use crate::error::Result;
use crate::factor::Settings;
use crate::images::Painting;
use crate::note::Note;
use crate::render::GBuffer;
use crate::sample::{Geometry, PaintedView};

/// Which estimates a reading makes (each can be turned off to fit the paintings as painted).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reading {
    /// Flat tones become the smooth shading between their edges ([`tones`]).
    pub smooth_tones: bool,
    /// Each view's light is registered to where the painting was shaded from ([`register`]).
    pub register_light: bool,
    /// Strokes that do not belong to the shading are repainted with the shading around them
    /// ([`strays`]).
    pub repaint_strays: bool,
}

impl Default for Reading {
    fn default() -> Self {
        Reading { smooth_tones: true, register_light: true, repaint_strays: true }
    }
}

impl Reading {
    /// Paintings fitted as painted.
    pub fn none() -> Reading {
        Reading { smooth_tones: false, register_light: false, repaint_strays: false }
    }
}

/// What a reading found: the views as read (their paintings and light as evidence) and one
/// note per thing it changed.
pub struct Evidence {
    pub views: Vec<PaintedView>,
    pub notes: Vec<Note>,
}

/// Reads painted views against the G-buffers they were sampled from (one per view).
pub struct Reader<'a> {
    reading: Reading,
    gbuffers: &'a [&'a GBuffer],
}

/// A second reading of a toned painting without its strays is kept only when the factored
/// fit, under the light it registered, misses the painting by at most this relative RMS:
/// beyond 1 it explains less than a black material would.
const UNEXPLAINED_FIT: f64 = 1.0;

/// How far a toned view's tones may be left under the scene's light
/// ([`tones::Luminance::outside`]) before [`Pass::turn_on_tones`] also tries the lights its
/// brightest tone points to: the tones' quantization leaves clean and brushed paintings well
/// inside this, a glossy painting lit from elsewhere far outside it.
const UNEXPLAINED_TONES: f64 = 0.1;

impl<'a> Reader<'a> {
    pub fn new(reading: Reading, gbuffers: &'a [&'a GBuffer]) -> Reader<'a> {
        Reader { reading, gbuffers }
    }

    /// Reads `views` (module documentation). Strays found in flat tones of a single view
    /// are left out and the view read again from the start without them; that second
    /// reading is kept unless the fit cannot explain it at all ([`UNEXPLAINED_FIT`]).
    pub fn read(&self, views: Vec<PaintedView>) -> Result<Evidence> {
        let again = views.len() == 1 && self.reading.smooth_tones && self.reading.repaint_strays;
        let given = again.then(|| views.clone());
        let first = Pass::new(views, self.gbuffers, self.reading).run()?;
        let (Some(mut given), Some(strays)) = (given, first.strays.clone()) else { return Ok(first.evidence()) };
        if !strays.toned {
            return Ok(first.evidence());
        }
        for (view, pixels) in given.iter_mut().zip(&strays.per_view) {
            for &k in pixels {
                if std::mem::replace(&mut view.geometry.usable[k], false) {
                    view.geometry.left_out += 1;
                }
            }
        }
        let second = Pass::new(given, self.gbuffers, Reading { repaint_strays: false, ..self.reading }).run()?;
        if second.turns.iter().any(|t| !t.by_tones && t.after > UNEXPLAINED_FIT) {
            return Ok(first.evidence());
        }
        let strays = strays::Strays { left_out: true, ..strays };
        let mut evidence = second.evidence();
        evidence.notes.extend(strays.notes(&evidence.views));
        Ok(evidence)
    }
}

/// One reading of the views, step by step (module documentation); its state is what the
/// steps found so far.
struct Pass<'a> {
    views: Vec<PaintedView>,
    gbuffers: &'a [&'a GBuffer],
    reading: Reading,
    /// Each view's geometry under the scene's light, as given.
    scene: Vec<Geometry>,
    /// The toned views (by index) and their tones.
    toned: Vec<(usize, tones::Toned)>,
    /// Each view's light as registered (empty when the light is not registered).
    turns: Vec<register::Turn>,
    /// Every registration's proposal per view (rotation and the fit's gain), for toned views
    /// to judge on their tones.
    proposals: Vec<Vec<(DQuat, f64)>>,
    /// Per toned view, its tones read under the light kept.
    held: Vec<Option<tones::Luminance>>,
    /// The strays repainted, if any.
    strays: Option<strays::Strays>,
    notes: Vec<Note>,
}

impl<'a> Pass<'a> {
    fn new(views: Vec<PaintedView>, gbuffers: &'a [&'a GBuffer], reading: Reading) -> Pass<'a> {
        Pass { views, gbuffers, reading, scene: Vec::new(), toned: Vec::new(), turns: Vec::new(), proposals: Vec::new(), held: Vec::new(), strays: None, notes: Vec::new() }
    }

    fn run(mut self) -> Result<Pass<'a>> {
        // The paintings as painted, for a toned painting's first registration.
        let as_painted: Option<Vec<Painting>> =
            (self.reading.smooth_tones && self.reading.register_light).then(|| self.views.iter().map(|v| v.painting.clone()).collect());
        if self.reading.smooth_tones {
            self.smooth_tones();
        }
        self.scene = self.views.iter().map(|v| v.geometry.clone()).collect();
        self.turns = match as_painted {
            Some(painted) if !self.toned.is_empty() => match self.register_as_painted(painted)? {
                Some(turns) => turns,
                None => self.register()?,
            },
            _ => self.register()?,
        };
        self.proposals = self.turns.iter().map(|t| vec![(t.proposed, t.proposed_gain)]).collect();
        if self.reading.repaint_strays {
            self.repaint_strays()?;
        }
        self.judge_toned_turns();
        for (view, turn) in self.views.iter().zip(&self.turns) {
            if turn.moved() {
                self.notes.push(register::note(view, turn));
            }
        }
        self.refine_tones();
        Ok(self)
    }

    fn evidence(self) -> Evidence {
        Evidence { views: self.views, notes: self.notes }
    }

    fn smooth_tones(&mut self) {
        for (i, view) in self.views.iter_mut().enumerate() {
            if let Some(t) = tones::smooth(view) {
                self.notes.push(t.note(&view.name));
                self.toned.push((i, t));
            }
        }
    }

    /// Each view's light registered on the factored fit ([`register::register`]); none
    /// when the light is not registered.
    fn register(&mut self) -> Result<Vec<register::Turn>> {
        match self.reading.register_light {
            true => register::register(&mut self.views, self.gbuffers, &Settings::default()),
            false => Ok(Vec::new()),
        }
    }

    /// The light of toned paintings registered on their steps as painted (`painted`: the
    /// paintings before their tones were smoothed), when that is clear: every view's turn is
    /// kept by [`register::register`]'s own test. Then the views take the turned geometry and
    /// the turns are returned; else `None`, nothing changed. A step's quantization error sits
    /// about the shading on both sides of its edge, while the interpolation between edges is a
    /// guess that holds the light back. Not under a headlight, where one painting shows one
    /// angle and its steps cannot place the light.
    fn register_as_painted(&mut self, painted: Vec<Painting>) -> Result<Option<Vec<register::Turn>>> {
        let headlit = self.views.iter().any(|v| crate::factor::headlit(v.geometry.pixels.iter().flatten().map(|p| (p.query.l, p.query.v))));
        if headlit {
            return Ok(None);
        }
        // The smoothed paintings are not copied, only what registration reads beside them.
        let mut painted: Vec<PaintedView> = self
            .views
            .iter()
            .zip(painted)
            .map(|(v, painting)| PaintedView { name: v.name.clone(), source: v.source.clone(), geometry: v.geometry.clone(), painting })
            .collect();
        let turns = register::register(&mut painted, self.gbuffers, &Settings::default())?;
        if !turns.iter().all(register::Turn::moved) {
            return Ok(None);
        }
        for (view, p) in self.views.iter_mut().zip(painted) {
            view.geometry = p.geometry;
        }
        Ok(Some(turns))
    }

    /// Stray strokes repainted ([`strays::repaint`]); with them gone the painter's light may
    /// show more clearly, so it is searched again, and a view keeps its first turn unless the
    /// new one explains it better.
    fn repaint_strays(&mut self) -> Result<()> {
        let tones_of: Vec<Option<&tones::Toned>> = (0..self.views.len()).map(|v| self.toned.iter().find(|(i, _)| *i == v).map(|(_, t)| t)).collect();
        let Some(found) = strays::repaint(&mut self.views, &Settings::default(), &tones_of)? else { return Ok(()) };
        self.notes.extend(found.notes(&self.views));
        // A repainted stray's tone interval is the stroke's, not the shading's.
        for (i, t) in self.toned.iter_mut() {
            let stray: std::collections::HashSet<usize> = found.per_view[*i].iter().copied().collect();
            t.bounds.retain(|(k, _)| !stray.contains(k));
        }
        self.strays = Some(found);
        let again = self.register()?;
        for ((turn, again), proposed) in self.turns.iter_mut().zip(again).zip(self.proposals.iter_mut()) {
            proposed.push((again.proposed, again.proposed_gain));
            if again.moved() {
                *turn = again;
            }
        }
        Ok(())
    }

    /// A toned view's light registered on the interpolation between its tone edges is a
    /// guess; the edges themselves are the evidence. The turn is undone when the scene's light
    /// holds the tones clearly better ([`tones::held`]); where the tones cannot tell (a Gooch
    /// painting's two or three, under a headlight), the turn stays. A toned view whose light
    /// the factored fit would not turn may still be turned on its tones
    /// ([`Pass::turn_on_tones`]).
    fn judge_toned_turns(&mut self) {
        self.held = self.toned.iter().map(|_| None).collect();
        for k in 0..self.toned.len() {
            let i = self.toned[k].0;
            // No turns at all when the light is not registered.
            if self.turns.get(i).is_none() {
                continue;
            }
            if !self.turns[i].moved() {
                if let Some((turn, reading)) = self.turn_on_tones(k) {
                    self.turns[i] = turn.unwrap_or(self.turns[i]);
                    self.held[k] = Some(reading);
                }
                continue;
            }
            let toned = &self.toned[k].1;
            let turned = tones::held(&self.views[i], toned);
            let registered = std::mem::replace(&mut self.views[i].geometry, self.scene[i].clone());
            let scene = tones::held(&self.views[i], toned);
            match (turned, scene) {
                (Some(turned), Some(scene)) if scene.outside() < (1.0 - register::MIN_GAIN) * turned.outside() => {
                    self.turns[i] = register::Turn::kept(self.turns[i].before);
                    self.held[k] = Some(scene);
                }
                (turned, _) => {
                    self.views[i].geometry = registered;
                    self.held[k] = turned;
                }
            }
        }
    }

    /// The light of toned view `toned[k]`, which the factored fit did not turn (its geometry
    /// the scene's), judged on its tones: the search's proposals and, where the scene's light
    /// leaves the tones unexplained ([`UNEXPLAINED_TONES`]), the lights its brightest tone
    /// points to ([`register::brightest_turns`]) are read under each ([`tones::held`]), and
    /// the best is taken when its tones' misfit is under [`register::CLEAR_GAIN`] of the
    /// scene's light's, or [`register::MIN_GAIN`] under it where the factored fit gained as
    /// much from the same turn (the two judges agree). Returns the turn taken (`None`: the
    /// light stays) and the reading under the light kept; `None` when the tones give no
    /// reading.
    fn turn_on_tones(&mut self, k: usize) -> Option<(Option<register::Turn>, tones::Luminance)> {
        let (i, toned) = (self.toned[k].0, &self.toned[k].1);
        let (g, scene) = (self.gbuffers[i], &self.scene[i]);
        let view = &mut self.views[i];
        let at_scene = tones::held(view, toned)?;
        let brightest = match at_scene.outside() > UNEXPLAINED_TONES {
            true => register::brightest_turns(g, &toned.brightest()),
            false => Vec::new(),
        };
        let candidates = self.proposals[i].iter().copied().chain(brightest.into_iter().map(|q| (q, 1.0)));
        let mut best: Option<(DQuat, tones::Luminance, f64, f64)> = None;
        for (q, fit_gain) in candidates.filter(|(q, _)| q.to_axis_angle().1 > 0.0) {
            view.geometry = register::turned(g, scene, q);
            if let Some(reading) = tones::held(view, toned) {
                let outside = reading.outside();
                if best.as_ref().is_none_or(|b| outside < b.2) {
                    best = Some((q, reading, outside, fit_gain));
                }
            }
        }
        let gain = (1.0 - register::MIN_GAIN) * at_scene.outside();
        match best {
            // Strictly less: a painting whose tones every reading holds exactly cannot tell.
            Some((q, reading, outside, fit_gain))
                if outside < register::CLEAR_GAIN * at_scene.outside() || (outside < gain && fit_gain <= 1.0 - register::MIN_GAIN) =>
            {
                view.geometry = register::turned(g, scene, q);
                Some((Some(register::Turn::by(q, at_scene.outside(), outside, true)), reading))
            }
            _ => {
                view.geometry = scene.clone();
                Some((None, at_scene))
            }
        }
    }

    /// Each toned view's tones read through the lobe family that holds them best, under the
    /// light kept ([`tones::refine`]).
    fn refine_tones(&mut self) {
        for ((i, t), held) in self.toned.iter().zip(std::mem::take(&mut self.held)) {
            if let Some((lobe, alpha)) = tones::refine(&mut self.views[*i], t, held) {
                let width = if lobe.has_width() { lobe.width_of(alpha) } else { String::new() };
                self.notes.push(Note::TonesLobe { painting: self.views[*i].name.clone(), lobe: lobe.name(), width });
            }
        }
    }
}
