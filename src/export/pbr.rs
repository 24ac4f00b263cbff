//! The glTF 2.0 metallic-roughness material (glTF 2.0 specification, Appendix B) as a
//! [`Reflectance`], in brdfpaint's units.
//!
//! **Units.** A brdfpaint material is the shading $S$ a pixel shows under a unit white light
//! (DESIGN.md), and a painter's white Lambertian sphere at full light is base colour 1
//! (`README`, "Lit spheres"): $S = c\cos\theta_l$ for a diffuse material of base colour $c$.
//! glTF's diffuse BRDF is $c/\pi$, so brdfpaint's unit light is a glTF light of irradiance
//! $\pi$ and
//! $$ S(l, v) = \pi\, f_{\mathrm{glTF}}(l, v)\, \cos\theta_l . $$
//!
//! **The BRDF** (Appendix B, separable Smith masking as the specification writes it), with
//! $\alpha = r^2$, $x = (1 - |\mathbf v\cdot\mathbf h|)^5$, $F_d = 0.04 + 0.96\,x$:
//! $$ f = (1 - m)\Big[(1 - F_d)\frac{c}{\pi} + F_d\, V D\Big] + m\,\big(c + (1 - c)\,x\big)\, V D $$
//! with GGX's $D$ and $V = G_1(l) G_1(v) / (4\cos\theta_l\cos\theta_v)$
//! ([`crate::brdf::lobe::specular_shape`] is $\cos\theta_l V D$ and $x$).

use std::f64::consts::PI;

use crate::brdf::lobe::specular_shape;
use crate::brdf::Reflectance;
use crate::factor::Query;
use glam::DVec3;

/// Schlick's $F_0$ of a glTF dielectric (index of refraction 1.5).
pub use crate::brdf::lobe::DIELECTRIC_F0;

/// The smallest roughness a fit gives: $\alpha = 0.03^2$ is narrower than any table node
/// resolves, and renderers clamp lower values anyway.
pub const MIN_ROUGHNESS: f64 = 0.03;

/// A glTF metallic-roughness material, with `KHR_materials_specular` where its dielectric
/// reflects more than core glTF's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pbr {
    /// `baseColorFactor`'s RGB, linear, in [0, 1].
    pub base_color: [f64; 3],
    /// `metallicFactor`, in [0, 1].
    pub metallic: f64,
    /// `roughnessFactor`, in [[`MIN_ROUGHNESS`], 1].
    pub roughness: f64,
    /// The dielectric's Schlick $F_0$, in [[`DIELECTRIC_F0`], 1]: core glTF's above it is
    /// `KHR_materials_specular` with a grey `specularColorFactor` of $F_0 / 0.04$ and
    /// `specularFactor` 1 (so $F_{90} = 1$, as in core glTF).
    pub specular_f0: f64,
    /// `KHR_materials_clearcoat`'s layer, when the material has one.
    pub coat: Option<Coat>,
    /// `KHR_materials_sheen`'s layer, when the material has one.
    pub sheen: Option<Sheen>,
}

/// A sheen (`KHR_materials_sheen`): cloth's retro-reflection at grazing angles, the Charlie
/// distribution of Estevez and Kulla, $D = (2 + 1/\alpha)\sin^{1/\alpha}\theta_h / 2\pi$ with
/// $\alpha$ = roughness², and Neubelt and Pettineo's visibility $V = 1 / (4(\cos\theta_l +
/// \cos\theta_v - \cos\theta_l\cos\theta_v))$ (the extension's simpler choice, and the
/// analytic velvet's). The rest is dimmed by its albedo, $1 - \max(\text{colour})\,
/// E(\cos)$, the smaller at the light and at the view (as the glTF Sample Viewer does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheen {
    /// `sheenColorFactor`, linear, in [0, 1].
    pub color: [f64; 3],
    /// `sheenRoughnessFactor`, in [[`MIN_SHEEN_ROUGHNESS`], 1].
    pub roughness: f64,
}

/// The smallest sheen roughness a fit gives: $\alpha = 0.07^2$ makes $D$'s exponent 200.
pub const MIN_SHEEN_ROUGHNESS: f64 = 0.07;

impl Sheen {
    /// $\pi \cos\theta_l D V$ at unit colour: the sheen's shading per unit `color`.
    pub fn shape(roughness: f64, q: &Query) -> f64 {
        let (cl, cv) = (q.l.z, q.v.z);
        if cl <= 0.0 || cv <= 0.0 {
            return 0.0;
        }
        PI * cl * charlie_d(roughness, q.h().z) * neubelt_v(cl, cv)
    }

    /// The factor the rest of the material is dimmed by at `q` (type documentation).
    pub fn dimming(&self, q: &Query) -> f64 {
        let m = self.color.iter().fold(0.0f64, |a, &b| a.max(b));
        1.0 - m * albedo(self.roughness, q.l.z).max(albedo(self.roughness, q.v.z))
    }
}

fn charlie_d(roughness: f64, cos_h: f64) -> f64 {
    let inv = 1.0 / (roughness * roughness).max(1e-3);
    let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
    (2.0 + inv) * sin_h.powf(inv) / (2.0 * PI)
}

fn neubelt_v(cl: f64, cv: f64) -> f64 {
    1.0 / (4.0 * (cl + cv - cl * cv))
}

/// Nodes of the sheen's directional-albedo table: roughness and cosine.
const ALBEDO_ROUGHNESS: usize = 32;
const ALBEDO_COSINES: usize = 32;

/// The sheen's directional albedo $E(\mu) = \int D V \cos\theta_l\, d\omega_l$ at view
/// cosine $\mu$ (white colour), from a table integrated once (bilinear between nodes).
fn albedo(roughness: f64, mu: f64) -> f64 {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| {
        let mut t = Vec::with_capacity(ALBEDO_ROUGHNESS * ALBEDO_COSINES);
        for i in 0..ALBEDO_ROUGHNESS {
            let r = i as f64 / (ALBEDO_ROUGHNESS - 1) as f64;
            for j in 0..ALBEDO_COSINES {
                t.push(integrate_albedo(r.max(MIN_SHEEN_ROUGHNESS), (j as f64 / (ALBEDO_COSINES - 1) as f64).max(1e-3)));
            }
        }
        t
    });
    let at = |x: f64, n: usize| {
        let x = x.clamp(0.0, 1.0) * (n - 1) as f64;
        let i = (x.floor() as usize).min(n - 2);
        (i, x - i as f64)
    };
    let ((i, fr), (j, fm)) = (at(roughness, ALBEDO_ROUGHNESS), at(mu, ALBEDO_COSINES));
    let v = |i: usize, j: usize| table[i * ALBEDO_COSINES + j];
    (1.0 - fr) * ((1.0 - fm) * v(i, j) + fm * v(i, j + 1)) + fr * ((1.0 - fm) * v(i + 1, j) + fm * v(i + 1, j + 1))
}

/// $E(\mu)$ by the midpoint rule, uniform in $\cos\theta_l$ and azimuth ($d\omega = d\mu\,
/// d\varphi$).
fn integrate_albedo(roughness: f64, mu: f64) -> f64 {
    const N: usize = 96;
    let v = DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let mut sum = 0.0;
    for a in 0..N {
        let cl = (a as f64 + 0.5) / N as f64;
        let sl = (1.0 - cl * cl).sqrt();
        for b in 0..2 * N {
            let phi = PI * (b as f64 + 0.5) / N as f64;
            let l = DVec3::new(sl * phi.cos(), sl * phi.sin(), cl);
            sum += charlie_d(roughness, (l + v).normalize().z) * neubelt_v(cl, mu) * cl;
        }
    }
    sum * (1.0 / N as f64) * (PI / N as f64)
}

/// A clear coat (`KHR_materials_clearcoat`): a dielectric layer of index of refraction 1.5
/// over the material, its own GGX lobe of `roughness` weighted by `factor`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coat {
    /// `clearcoatFactor`, in [0, 1].
    pub factor: f64,
    /// `clearcoatRoughnessFactor`, in [[`MIN_ROUGHNESS`], 1].
    pub roughness: f64,
}

impl Pbr {
    /// A core glTF material (no extension).
    pub fn core(base_color: [f64; 3], metallic: f64, roughness: f64) -> Pbr {
        Pbr { base_color, metallic, roughness, specular_f0: DIELECTRIC_F0, coat: None, sheen: None }
    }

    /// The shading at `q` as $a + b\,c$ in the base colour $c$ (the material's own base
    /// colour is not used). A coat of factor $k$ dims the rest by $1 - k F(\mathbf n \cdot
    /// \mathbf v)$ and adds its own specular lobe, $k F(\mathbf v \cdot \mathbf h)\,\pi
    /// \cos\theta_l V D$, Schlick's $F$ with $F_0$ 0.04 (`KHR_materials_clearcoat`, as the
    /// glTF Sample Viewer renders it): still affine in $c$.
    /// A sheen dims this part by [`Sheen::dimming`] and adds its own, channel by channel
    /// ([`Pbr::shading`]).
    pub fn affine(&self, q: &Query) -> (f64, f64) {
        let (a, b) = self.coated(q);
        let k = self.sheen.map_or(1.0, |s| s.dimming(q));
        (k * a, k * b)
    }

    /// [`Pbr::affine`] without the sheen.
    fn coated(&self, q: &Query) -> (f64, f64) {
        let (a, b) = affine_in_base_color(self.metallic, self.roughness, self.specular_f0, q);
        let Some(coat) = self.coat else { return (a, b) };
        if q.l.z <= 0.0 || q.v.z <= 0.0 {
            return (0.0, 0.0);
        }
        let schlick = |x: f64| DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * x;
        let dim = 1.0 - coat.factor * schlick((1.0 - q.v.z.min(1.0)).powi(5));
        let (s, x) = specular_shape(q.l, q.v, coat.roughness * coat.roughness);
        (dim * a + coat.factor * schlick(x) * PI * s, dim * b)
    }

    /// `KHR_materials_specular`'s grey `specularColorFactor`, when the material needs it.
    pub fn specular_color(&self) -> Option<f64> {
        (self.specular_f0 > DIELECTRIC_F0 * (1.0 + 1e-9)).then(|| self.specular_f0 / DIELECTRIC_F0)
    }
}

/// What the shading of a [`Pbr`] is made of at one query, per channel: $S = a + b\,c$ for
/// base colour $c$ at fixed metallic, roughness and dielectric $F_0$ (the BRDF is linear in
/// $c$; `KHR_materials_specular` mixes diffuse and specular by the same Schlick term).
pub fn affine_in_base_color(metallic: f64, roughness: f64, f0: f64, q: &Query) -> (f64, f64) {
    let cl = q.l.z;
    if cl <= 0.0 || q.v.z <= 0.0 {
        return (0.0, 0.0);
    }
    let alpha = roughness * roughness;
    // $s = \cos\theta_l V D$, and Schlick's $x$.
    let (s, x) = specular_shape(q.l, q.v, alpha);
    let fd = f0 + (1.0 - f0) * x;
    // Dielectric: $\pi\cos\theta_l[(1 - F_d) c/\pi + F_d V D]$.
    let (a_d, b_d) = (PI * fd * s, (1.0 - fd) * cl);
    // Metal: $\pi\cos\theta_l V D (c + (1 - c) x)$.
    let (a_m, b_m) = (PI * s * x, PI * s * (1.0 - x));
    ((1.0 - metallic) * a_d + metallic * a_m, (1.0 - metallic) * b_d + metallic * b_m)
}

impl Reflectance for Pbr {
    /// $S = \pi f \cos\theta_l$ (module documentation).
    fn shading(&self, q: &Query) -> [f64; 3] {
        let (a, b) = self.affine(q);
        let sheen = self.sheen.map_or([0.0; 3], |s| s.color.map(|c| c * Sheen::shape(s.roughness, q)));
        [0, 1, 2].map(|c| a + b * self.base_color[c] + sheen[c])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn white_dielectric_rough_is_near_lambert_in_painter_units() {
        // Head-on light and view: S = (1 - F0) c + π F0 D V for α = 1, where D = 1/π and
        // V = 1/4 (G1 = 1 at normal incidence): 0.96 c + 0.04/4.
        let pbr = Pbr::core([1.0, 0.5, 0.0], 0.0, 1.0);
        let s = pbr.shading(&Query::at(DVec3::Z, DVec3::Z));
        for (c, &base) in [1.0, 0.5, 0.0].iter().enumerate() {
            let expected = 0.96 * base + 0.04 / 4.0;
            assert!((s[c] - expected).abs() < 1e-9, "channel {c}: {} vs {expected}", s[c]);
        }
    }

    #[test]
    fn a_clear_coat_mixes_its_lobe_by_its_fresnel() {
        // Head-on both Fresnel terms are F0 = 0.04 (k = 1), and the coat's π cos θ_l V D =
        // π / (π α²) / 4 = 4 at roughness 0.5 (α = 0.25).
        let base = Pbr::core([0.5, 0.2, 0.1], 0.0, 0.8);
        let coated = Pbr { coat: Some(Coat { factor: 1.0, roughness: 0.5 }), ..base };
        let q = Query::at(DVec3::Z, DVec3::Z);
        let (b, c) = (base.shading(&q), coated.shading(&q));
        for k in 0..3 {
            assert!((c[k] - (0.96 * b[k] + 0.04 * 4.0)).abs() < 1e-9, "channel {k}: {} vs {}", c[k], b[k]);
        }
        // A coat of factor 0 is no coat.
        let none = Pbr { coat: Some(Coat { factor: 0.0, roughness: 0.1 }), ..base };
        let q = Query::at(DVec3::new(0.6, 0.0, 0.8), DVec3::new(-0.3, 0.1, 0.95).normalize());
        assert_eq!(none.shading(&q), base.shading(&q));
    }

    #[test]
    fn metal_has_no_diffuse_and_below_horizon_is_dark() {
        let pbr = Pbr::core([0.9, 0.6, 0.3], 1.0, 0.4);
        // Off the mirror direction by a wide angle, a narrow metal lobe is nearly black.
        let l = DVec3::new(0.8, 0.0, 0.6).normalize();
        let v = DVec3::new(0.8, 0.0, 0.6).normalize();
        let s = pbr.shading(&Query::at(l, v));
        assert!(s[0] < 0.05, "{s:?}");
        assert_eq!(pbr.shading(&Query::at(DVec3::new(0.0, 0.6, -0.8), DVec3::Z)), [0.0; 3]);
    }
}
