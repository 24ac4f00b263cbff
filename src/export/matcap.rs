//! A material as a MatCap: the unit sphere seen from the front, its disk inscribed in a
//! square image (pixel $(i, j)$ of $N$ at $x = 2(i + 1/2)/N - 1$, $y = 1 - 2(j + 1/2)/N$,
//! normal $(x, y, \sqrt{1 - x^2 - y^2})$, view $+z$), under a directional light or an
//! environment. The frame is the lit-sphere picture's (x right, y up, z to the viewer), so
//! a lit-sphere fit under its own light gives its picture back.
//!
//! Under an environment the pixel is $\int S(l, v)\, L(l)\, d\omega_l$ over the directions
//! above the pixel's horizon ([`crate::render::env`]'s integral), summed over a fixed set
//! of [`ENV_DIRECTIONS`] directions uniform on the sphere.
//!
//! A material with an analytic base splits into its diffuse and specular parts, each with the
//! term's factored correction applied: $B = a + k_d d + s(k_s + k_f x^5)$, so the diffuse
//! part is $(a + k_d d)\,m^{-1}(\prod p)$ and the specular part $s(k_s + k_f x^5)\, m^{-1}(\prod p)$.

use std::f64::consts::PI;

use glam::DVec3;

use crate::brdf::{Reflectance, SphereView};
use crate::factor::Query;
use crate::images::env::Environment;
use crate::error::{Error, Result};
use crate::images::encode_srgb8;
use crate::material::{Material, Term};

/// Directions an environment is integrated over, uniform on the sphere (Fibonacci):
/// 1024 put one within about 4° of any direction.
pub const ENV_DIRECTIONS: usize = 1024;

/// What lights the sphere.
pub enum Lighting<'a> {
    /// A unit white directional light from this direction (towards it).
    Light(DVec3),
    /// An environment in the picture's frame, turned about +y by degrees.
    Env(&'a Environment, f64),
}

/// A MatCap's pixels, row 0 at the top.
pub type Pixels = Vec<[f32; 3]>;

/// A MatCap image: the whole shading, and its diffuse and specular parts when the material
/// has an analytic base. Row 0 at the top; `mask` is true on the disk.
pub struct Matcap {
    pub size: usize,
    pub total: Pixels,
    pub parts: Option<(Pixels, Pixels)>,
    pub mask: Vec<bool>,
}

/// The normal under pixel (i, j) of an `n`-pixel MatCap, or `None` off the disk.
pub fn normal_at(i: usize, j: usize, n: usize) -> Option<DVec3> {
    let p = crate::material::Detail::texel_normal(n, i, j);
    let rr = p.length_squared();
    (rr < 1.0).then(|| DVec3::new(p.x, p.y, (1.0 - rr).sqrt()))
}

/// A term's shading split into (diffuse, specular); the specular part is zero without a base.
fn split(term: &Term, q: &Query) -> ([f64; 3], [f64; 3]) {
    let mut prod = [1.0; 3];
    for f in &term.factors {
        let x = f.lookup(q);
        prod = [0, 1, 2].map(|c| prod[c] * x[c]);
    }
    let correction = [0, 1, 2].map(|c| term.map.inverse(c, prod[c]));
    match &term.base {
        Some(b) => {
            let (d, s, x5) = b.lobe.shape(q.l, q.v, b.alpha);
            let diffuse = [0, 1, 2].map(|c| (b.ambient[c] + d * b.diffuse[c]) * correction[c]);
            let specular = [0, 1, 2].map(|c| s * (b.specular[c] + x5 * b.fresnel[c]) * correction[c]);
            (diffuse, specular)
        }
        None => (correction, [0.0; 3]),
    }
}

/// The material's (diffuse, specular) at a query, coefficients applied.
fn parts_at(material: &Material, q: &Query) -> ([f64; 3], [f64; 3]) {
    let (mut d, mut s) = ([0.0; 3], [0.0; 3]);
    for term in &material.terms {
        let w = term.coefficients.as_ref().map_or([1.0; 3], |c| c.lookup(q.uv));
        let (td, ts) = split(term, q);
        for c in 0..3 {
            d[c] += w[c] * td[c];
            s[c] += w[c] * ts[c];
        }
    }
    (d, s)
}

/// Unit directions uniform on the sphere (Fibonacci lattice).
fn sphere_directions(n: usize) -> Vec<DVec3> {
    let golden = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// The (diffuse, specular) a pixel of normal `n` shows under `lighting`.
fn pixel(material: &Material, n: DVec3, lights: &[(DVec3, [f64; 3])]) -> ([f64; 3], [f64; 3]) {
    let (mut d, mut s) = ([0.0; 3], [0.0; 3]);
    for &(l, e) in lights {
        // The surface hides what is below its horizon (render::env); a lone key light is
        // shaded on the unlit side too, as a painting is.
        if lights.len() > 1 && l.dot(n) <= 0.0 {
            continue;
        }
        let (pd, ps) = parts_at(material, &SphereView::query(n, l, DVec3::Z));
        for c in 0..3 {
            d[c] += pd[c] * e[c];
            s[c] += ps[c] * e[c];
        }
    }
    (d, s)
}

/// `material` as an `n`-pixel MatCap under `lighting`.
pub fn render(material: &Material, n: usize, lighting: &Lighting) -> Matcap {
    let lights: Vec<(DVec3, [f64; 3])> = match lighting {
        Lighting::Light(l) => vec![(l.normalize(), [1.0; 3])],
        Lighting::Env(env, rotate) => {
            let dw = 4.0 * PI / ENV_DIRECTIONS as f64;
            sphere_directions(ENV_DIRECTIONS).into_iter().map(|l| (l, env.radiance(l, *rotate).map(|x| x * dw))).collect()
        }
    };
    let has_base = material.terms.iter().any(|t| t.base.is_some());
    let mut m = Matcap { size: n, total: vec![[0.0; 3]; n * n], parts: None, mask: vec![false; n * n] };
    let mut parts = (vec![[0.0f32; 3]; n * n], vec![[0.0f32; 3]; n * n]);
    use rayon::prelude::*;
    // Each row's pixels on the disk: (diffuse, specular).
    type Row = Vec<Option<([f64; 3], [f64; 3])>>;
    let rows: Vec<Row> = (0..n)
        .into_par_iter()
        .map(|j| (0..n).map(|i| normal_at(i, j, n).map(|nrm| pixel(material, nrm, &lights))).collect())
        .collect();
    for (j, row) in rows.into_iter().enumerate() {
        for (i, px) in row.into_iter().enumerate() {
            if let Some((d, s)) = px {
                let k = j * n + i;
                m.mask[k] = true;
                m.total[k] = [0, 1, 2].map(|c| (d[c] + s[c]) as f32);
                parts.0[k] = d.map(|x| x as f32);
                parts.1[k] = s.map(|x| x as f32);
            }
        }
    }
    if has_base {
        m.parts = Some(parts);
    }
    m
}

/// The shading of `material` for a check against [`Reflectance`]: the MatCap's total is
/// this at each pixel under a light.
pub fn shading_at(material: &Material, n: DVec3, light: DVec3) -> [f64; 3] {
    material.shading(&SphereView::query(n, light.normalize(), DVec3::Z))
}

/// The MatCap as an 8-bit sRGB PNG with alpha (transparent off the disk; values clamped to
/// [0, 1], no tone mapping).
pub fn png_bytes(m: &Matcap) -> Result<Vec<u8>> {
    let rgba: Vec<u8> = m
        .total
        .iter()
        .zip(&m.mask)
        .flat_map(|(p, &on)| if on { [encode_srgb8(p[0]), encode_srgb8(p[1]), encode_srgb8(p[2]), 255] } else { [0; 4] })
        .collect();
    let img = image::RgbaImage::from_raw(m.size as u32, m.size as u32, rgba).ok_or_else(|| Error::input("MatCap buffer does not match its size"))?;
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).map_err(|e| Error::input(format!("cannot encode the MatCap PNG: {e}")))?;
    Ok(out.into_inner())
}

/// The MatCap as a float EXR, linear: layers `diffuse` and `specular` (channels
/// `diffuse.R`, …, `specular.A`, the OpenEXR layer naming Blender reads) when the material has
/// an analytic base, else one layer `R`, `G`, `B`, `A`. Alpha is 1 on the disk.
pub fn exr_bytes(m: &Matcap) -> Result<Vec<u8>> {
    use exr::prelude::*;
    let alpha: Vec<f32> = m.mask.iter().map(|&on| if on { 1.0 } else { 0.0 }).collect();
    let channel = |name: String, values: Vec<f32>| AnyChannel::new(name.as_str(), FlatSamples::F32(values));
    let rgba = |prefix: &str, px: &[[f32; 3]]| -> Vec<AnyChannel<FlatSamples>> {
        let mut out: Vec<_> = ["R", "G", "B"].iter().enumerate().map(|(c, n)| channel(format!("{prefix}{n}"), px.iter().map(|p| p[c]).collect())).collect();
        out.push(channel(format!("{prefix}A"), alpha.clone()));
        out
    };
    let channels = match &m.parts {
        Some((d, s)) => rgba("diffuse.", d).into_iter().chain(rgba("specular.", s)).collect::<Vec<_>>(),
        None => rgba("", &m.total),
    };
    let layer = Layer::new((m.size, m.size), LayerAttributes::named("matcap"), Encoding::FAST_LOSSLESS, AnyChannels::sort(channels.into()));
    let mut out = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer).write().to_buffered(&mut out).map_err(|e| crate::error::Error::input(format!("cannot encode the MatCap EXR: {e}")))?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::lobe::{Base, Lobe};
    use crate::factor::{FactorSpec, LogMap};
    use crate::material::{Factor, Kind};

    #[test]
    fn parts_sum_to_the_shading_of_a_based_material() {
        let base = Base { ambient: [0.01; 3], diffuse: [0.5, 0.3, 0.2], specular: [0.2; 3], fresnel: [0.1; 3], alpha: 0.3, lobe: Lobe::Ggx };
        let spec: FactorSpec = crate::factor::Settings::default().factors[0].clone();
        let factor = Factor { texels: (0..spec.res).map(|i| [1.0 + 0.2 * (i as f32 / spec.res as f32); 3]).collect(), spec };
        let term = Term { factors: vec![factor], map: LogMap::Identity { floor: [1e-6; 3] }, coefficients: None, base: Some(base) };
        let material = Material::new(Kind::Uniform, vec![term]);
        let light = DVec3::new(-0.4, 0.5, 0.77);
        let m = render(&material, 32, &Lighting::Light(light));
        let (d, s) = m.parts.as_ref().unwrap();
        let mut checked = 0;
        for j in 0..32 {
            for i in 0..32 {
                let Some(n) = normal_at(i, j, 32) else { continue };
                let want = shading_at(&material, n, light);
                let k = j * 32 + i;
                for c in 0..3 {
                    let got = (d[k][c] + s[k][c]) as f64;
                    assert!((got - want[c]).abs() < 1e-5 * (1.0 + want[c]), "pixel ({i}, {j}): {got} vs {}", want[c]);
                }
                checked += 1;
            }
        }
        assert!(checked > 700 && s.iter().any(|x| x[0] > 0.01));
    }
}
