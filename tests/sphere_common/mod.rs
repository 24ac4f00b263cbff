//! A lit-sphere picture of an analytic model, shared by the lit-sphere tests.

use brdfpaint::brdf::{Analytic, Reflectance, SphereView};
use brdfpaint::images::Painting;
use glam::DVec3;

/// `model` painted on a sphere of `res` pixels lit from `light`, placed at (`x0`, `y0`) in a
/// `w` × `h` picture on a white background: the truth times a white light.
pub fn sphere_picture(model: &Analytic, light: DVec3, res: usize, (w, h): (usize, usize), (x0, y0): (usize, usize)) -> Painting {
    let mut p = Painting::opaque(w, h, vec![[1.0; 3]; w * h]).unwrap();
    for px in SphereView::new(light, res).pixels() {
        let s = model.shading(&px.query);
        p.pixels[(y0 + px.pixel[1]) * w + x0 + px.pixel[0]] = s.map(|x| x as f32);
    }
    p
}
