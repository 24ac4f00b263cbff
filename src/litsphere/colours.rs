//! A lit sphere keeps its picture's colours under moved lights (issue 35).
//!
//! One picture shows one light and one view. Fitted as the thesis does (each channel on its
//! own, the mapping of least error), the factors extrapolate each channel on its own where
//! the picture is silent, and a grey MatCap can turn orange and cyan once the light moves
//! behind it. Two things cause it: the near-null direction of one view, which coupled
//! channels close ([`Channels::Coupled`]); and the offset and inverted mappings, which
//! subtract a constant after the product (eqs. 3.14, 3.16), so that where the product nears
//! it a small hue difference becomes a large one, which the identity mapping does not do.
//!
//! Painted colour comes first, and a fit that keeps it is never touched: [`invented`]
//! renders the material on a sphere under lights moved around it, and only a fit that
//! invents colours ([`INVENTED`]) is fitted again, [`TRIES`] in turn, until one keeps the
//! picture's colours (else the one that invents least is kept): each try gives up more of
//! the picture's fidelity than the one before.

use glam::DVec3;

use crate::brdf::{Reflectance, SphereView};
use crate::error::Result;
use crate::factor::cache::Cache;
use crate::factor::{Channels, Mapping, Settings};
use crate::images::palette::{Palette, FRAMES, INVENTED};
use crate::material::Material;
use crate::note::Note;
use crate::pipeline::{self, Fitted, Options};
use crate::sample::PaintedView;

/// The fits tried after the thesis's, in order: coupled channels, then coupled channels
/// with the identity mapping.
pub const TRIES: [(Channels, Mapping); 2] = [(Channels::Coupled, Mapping::Auto), (Channels::Coupled, Mapping::Identity)];

/// [`pipeline::fit`] of one lit-sphere view, fitted again with [`TRIES`] in turn while
/// `opts.keep_colours` and the material invents colours ([`choose`]), with a note when a try
/// is kept.
pub fn fit(view: &PaintedView, opts: &Options, cache: Option<&Cache>) -> Result<Fitted> {
    let views = std::slice::from_ref(view);
    let fitted = pipeline::fit(views, opts, cache)?;
    if !opts.keep_colours {
        return Ok(fitted);
    }
    let palette = Palette::of_painting(&view.painting);
    let first = invented(&fitted.material, &palette);
    let mut refits = Vec::new();
    let chosen = choose(first, |channels, mapping| {
        let o = Options { settings: Settings { channels, ..opts.settings.clone() }, mapping, ..opts.clone() };
        let refit = pipeline::fit(views, &o, cache)?;
        let after = invented(&refit.material, &palette);
        refits.push(refit);
        Ok(after)
    })?;
    Ok(match chosen {
        Some(Chosen { index, after }) => {
            let mut refit = refits.swap_remove(index);
            refit.notes.push(Note::KeptColours { identity: TRIES[index].1 == Mapping::Identity, before: first, after });
            refit
        }
        None => fitted,
    })
}

/// A try of [`TRIES`] kept over the thesis's fit: its index, and the share it invents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chosen {
    pub index: usize,
    pub after: f64,
}

/// Which fit keeps the picture's colours, given the share the thesis's fit invents (`first`)
/// and `invented_with`, which fits with a try's channels and mapping and says the share that
/// fit invents. The tries are made in turn while the best so far invents colours; the first
/// that does not (else the one that invents least) is chosen, `None` for the thesis's own.
pub fn choose(first: f64, mut invented_with: impl FnMut(Channels, Mapping) -> Result<f64>) -> Result<Option<Chosen>> {
    let (mut least, mut chosen) = (first, None);
    for (index, (channels, mapping)) in TRIES.into_iter().enumerate() {
        if least <= INVENTED {
            break;
        }
        let after = invented_with(channels, mapping)?;
        if after < least {
            (least, chosen) = (after, Some(Chosen { index, after }));
        }
    }
    Ok(chosen)
}

/// Pixels across the sphere ([`frame`]): 160 puts about 20,000 samples on the disk, and a
/// light 22.5° short of straight behind lights a crescent of about 100 of them (the
/// perspective view sees less of the far side than an orthographic one), so one pixel is
/// 1% of that frame, under the 5% a material may invent ([`INVENTED`]).
const ACROSS: usize = 160;

/// Lights around the vertical axis: twice [`FRAMES`], so one lands 22.5° short of straight
/// behind, where a perspective view of a model (the sweep of `study::colour`) sees lit rims
/// that a sphere lit from straight behind does not show.
const AROUND: usize = 2 * FRAMES;

/// The largest share, over [`AROUND`] white lights moved around the vertical axis from the
/// view, of a sphere's lit pixels (seen from +z as [`frame`] sees it; each frame's floor its
/// own brightest, as [`Palette::invented_among`] judges) that `palette` does not hold.
pub fn invented(material: &Material, palette: &Palette) -> f64 {
    // A light straight behind lights no point the view sees: that frame shows only the
    // floor of the light factor, no shading, and is left out.
    (0..AROUND)
        .filter(|&k| 2 * k != AROUND)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / AROUND as f64;
            palette.invented_among(&frame(material, DVec3::new(a.sin(), 0.0, a.cos())))
        })
        .fold(0.0, f64::max)
}

/// The sphere's colours under a white light towards `light` (view frame), one per pixel of
/// a perspective camera on +z that frames it as the presets frame a model
/// ([`crate::scene::preset::frame`]: 30° of field, the bounding sphere filling 85%): a model
/// is seen so in the viewer and the renders, and there each point's view direction turns by
/// up to the sphere's half-angle (13°) from the axis, so the rims meet the light at angles an
/// orthographic sphere does not show.
fn frame(material: &Material, light: DVec3) -> Vec<[f64; 3]> {
    use crate::scene::preset::{FRAME_FILL, FRAME_YFOV};
    let half_angle = (FRAME_FILL as f64 * (FRAME_YFOV as f64 / 2.0).tan()).atan();
    let eye = DVec3::new(0.0, 0.0, 1.0 / half_angle.sin());
    // The unit sphere's silhouette fills the square of ACROSS pixels.
    let across = half_angle.tan();
    let mut out = Vec::with_capacity(ACROSS * ACROSS);
    for j in 0..ACROSS {
        for i in 0..ACROSS {
            let (x, y) = ((i as f64 + 0.5) / ACROSS as f64 * 2.0 - 1.0, 1.0 - (j as f64 + 0.5) / ACROSS as f64 * 2.0);
            let ray = DVec3::new(x * across, y * across, -1.0).normalize();
            // The nearer intersection of eye + t·ray with the unit sphere.
            let b = eye.dot(ray);
            let disc = b * b - (eye.length_squared() - 1.0);
            if disc > 0.0 {
                let n = (eye + ray * (-b - disc.sqrt())).normalize();
                out.push(material.shading(&SphereView::query(n, light, -ray)));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::Analytic;
    use crate::factor::{prepare, Query};
    use crate::material::Provenance;
    use crate::factor::Pattern;

    /// A material fitted from one view of `model`'s sphere lit from `light`.
    fn fitted(model: &Analytic, light: DVec3, mapping: Mapping) -> (Material, Palette) {
        let view = crate::brdf::SphereView::new(light, 64);
        let (queries, values): (Vec<Query>, Vec<[f64; 3]>) = view.pixels().into_iter().map(|p| (p.query, model.shading(&p.query))).unzip();
        let settings = Settings::default();
        let prepared = prepare(&Pattern::new(queries, false), &settings).unwrap();
        let fit = prepared.solve(&values, mapping).unwrap();
        (Material::from_fit(&settings, &fit, Provenance::default()).unwrap(), Palette::new(&values))
    }

    #[test]
    fn a_tinted_lambertian_sphere_keeps_its_colour_and_a_grey_palette_refuses_it() {
        let model = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
        let (material, palette) = fitted(&model, DVec3::new(-0.3, 0.5, 1.0), Mapping::Identity);
        assert!(invented(&material, &palette) < 0.01, "{}", invented(&material, &palette));
        // The same material judged against grey paintings: every lit pixel is off them.
        let grey = Palette::new(&[[0.5; 3], [0.2; 3]]);
        assert!(invented(&material, &grey) > 0.99, "{}", invented(&material, &grey));
    }
}
