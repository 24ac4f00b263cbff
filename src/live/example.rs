//! The bundled example painting: what a first run of the viewer fits and shows.

use super::canvas::{blank, Painting};
use super::view::PaintView;

/// The bundled default painting: glossy orange ceramic with a cool fill on its unlit side,
/// painted procedurally at the view's own samples. Its fit is the material a first run shows.
pub fn example_painting(view: &PaintView) -> Painting {
    // What a painter puts down: a base colour shaded by cos θ_l, a soft white highlight
    // around the mirror direction ($n \cdot h$), and a cool fill on the unlit side.
    let base = [0.80, 0.36, 0.12];
    let fill = [0.030, 0.040, 0.075];
    let mut p = blank(view.width, view.height).expect("a view has a valid size");
    for slot in &view.slots {
        let (l, v) = (slot.query.l, slot.query.v);
        let h = (l + v).normalize_or(glam::DVec3::Z);
        let lit = l.z.max(0.0);
        let highlight = 0.55 * h.z.max(0.0).powf(80.0) * lit.sqrt();
        // The painted colour is the shading function times the light.
        let c = [0, 1, 2].map(|k| ((base[k] * lit + highlight + fill[k] * (1.0 - 0.5 * lit)) * slot.light[k]) as f32);
        p.pixels[slot.pixel as usize] = c;
        p.alpha[slot.pixel as usize] = 1.0;
    }
    p
}
