//! Analytic reflectance models in the local shading frame ($z$ = normal, $x$ = tangent,
//! $y$ = bitangent). `l` points toward the light, `v` toward the viewer, both unit vectors;
//! $\mathbf h = \mathrm{normalize}(\mathbf l + \mathbf v)$ and $\cos\theta_k = k_z$.
//!
//! They serve as ground truth for tests, demos and synthetic paintings. Every physical model
//! here is reciprocal and non-negative; [`Analytic::Gooch`] is a non-photorealistic *shading*
//! model defined on the whole sphere and is not a physical BRDF.

use glam::DVec3;
use std::f64::consts::PI;

use super::lobe::ggx_d;

use super::Reflectance;
use crate::factor::Query;

/// Analytic reflectance models in the local shading frame (z = normal).
///
/// All colours are linear RGB.
#[derive(Clone, Debug, PartialEq)]
pub enum Analytic {
    /// Lambertian diffuse: $f = \rho / \pi$.
    Lambert { albedo: [f64; 3] },
    /// Normalized Blinn-Phong:
    /// $f = k_d/\pi + k_s \frac{n+8}{8\pi} (\mathbf n\cdot\mathbf h)^n$.
    BlinnPhong { diffuse: [f64; 3], specular: [f64; 3], exponent: f64 },
    /// Cook-Torrance with the GGX (Trowbridge-Reitz) distribution, Schlick's Fresnel and the
    /// separable Smith masking-shadowing term, $\alpha = \text{roughness}^2$:
    /// $f = k_d/\pi + \frac{D(\mathbf h)\,F(\mathbf l\cdot\mathbf h)\,G(\mathbf l,\mathbf v)}
    /// {4\cos\theta_l\cos\theta_v}$.
    Ggx { diffuse: [f64; 3], f0: [f64; 3], roughness: f64 },
    /// Isotropic Ward:
    /// $f = k_d/\pi + k_s \frac{\exp(-\tan^2\theta_h/\alpha^2)}
    /// {4\pi\alpha^2\sqrt{\cos\theta_l\cos\theta_v}}$.
    Ward { diffuse: [f64; 3], specular: [f64; 3], alpha: f64 },
    /// Oren-Nayar (the standard "qualitative" model), roughness `sigma` in radians:
    /// $f = \frac{\rho}{\pi}\left(A + B\max(0,\cos(\phi_l-\phi_v))\sin\alpha\tan\beta\right)$,
    /// $\alpha = \max(\theta_l,\theta_v)$, $\beta = \min(\theta_l,\theta_v)$.
    OrenNayar { albedo: [f64; 3], sigma: f64 },
    /// Minnaert (velvet for $k<1$, lunar-like darkening for $k>1$):
    /// $f = \frac{\rho}{\pi}(\cos\theta_l\cos\theta_v)^{k-1}$.
    ///
    /// For $k<1$ the BRDF grows without bound toward grazing angles, so its directional
    /// albedo exceeds 1 very close to the horizon; that is a property of the model.
    Minnaert { albedo: [f64; 3], k: f64 },
    /// Gooch warm-to-cool shading (non-photorealistic). Its *shading* is defined on the whole
    /// sphere of light directions, including the unlit side:
    /// $S = \mathrm{mix}(\text{cool}, \text{warm}, (1 + l_z)/2)$.
    ///
    /// This is a shading model, not a physical BRDF: it is not reciprocal and does not
    /// conserve energy. [`Analytic::brdf`] returns $S / \max(l_z, 10^{-3})$ on the lit side
    /// and zero on the unlit side, so only [`Analytic::shading`] describes the unlit side.
    Gooch { warm: [f64; 3], cool: [f64; 3] },
    /// Modified Phong (Lafortune and Willems 1994), reciprocal and normalized:
    /// $f = k_d/\pi + k_s \frac{n+2}{2\pi} \max(0, \mathbf r\cdot\mathbf v)^n$ with
    /// $\mathbf r = 2(\mathbf n\cdot\mathbf l)\mathbf n - \mathbf l$, the mirror of $l$.
    Phong { diffuse: [f64; 3], specular: [f64; 3], exponent: f64 },
    /// Isotropic Ashikhmin-Shirley (2000), $n_u = n_v = n$, with its coupled diffuse term:
    /// $f_s = \frac{n+1}{8\pi} \frac{(\mathbf n\cdot\mathbf h)^n}
    /// {(\mathbf h\cdot\mathbf l)\max(\cos\theta_l,\cos\theta_v)} F(\mathbf h\cdot\mathbf l)$,
    /// $f_d = \frac{28 R_d}{23\pi}(1 - R_s)\big(1 - (1 - \tfrac{\cos\theta_l}{2})^5\big)
    /// \big(1 - (1 - \tfrac{\cos\theta_v}{2})^5\big)$, $F$ Schlick's with $F_0 = R_s$.
    /// Its Fresnel brightens grazing (rim) light, which depends on $\theta_d$.
    AshikhminShirley { diffuse: [f64; 3], specular: [f64; 3], exponent: f64 },
    /// Velvet: Lambertian diffuse plus a sheen lobe, the "Charlie" distribution of Estevez and
    /// Kulla (2017), $D = \frac{(2 + 1/r)\sin^{1/r}\theta_h}{2\pi}$, with Neubelt and
    /// Pettineo's visibility $V = 1 / (4(\cos\theta_l + \cos\theta_v -
    /// \cos\theta_l\cos\theta_v))$: $f = k_d/\pi + k_{sh} D V$. Bright at grazing light and
    /// view, dark facing the viewer.
    Velvet { diffuse: [f64; 3], sheen: [f64; 3], roughness: f64 },
    /// [`Analytic::Gooch`] with a Blinn-Phong highlight on the lit side (Gooch et al. 1998):
    /// $S = \mathrm{mix}(\text{cool}, \text{warm}, (1 + l_z)/2) + k_s
    /// (\mathbf n\cdot\mathbf h)^n \max(l_z, 0)$. A shading model, not a physical BRDF.
    GoochSpecular { warm: [f64; 3], cool: [f64; 3], specular: [f64; 3], exponent: f64 },
}

/// $\mathbf a \cdot s$ for an RGB triple.
fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// $\mathbf a + \mathbf b$ for RGB triples.
fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Smith's masking term for GGX, one direction:
/// $G_1(\omega) = \frac{2\cos\theta}{\cos\theta + \sqrt{\alpha^2 + (1-\alpha^2)\cos^2\theta}}$.
fn ggx_g1(cos: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let denom = cos + (a2 + (1.0 - a2) * cos * cos).sqrt();
    // Only called with cos > 0, so denom > 0; the guard keeps a degenerate input finite.
    if denom > 0.0 { 2.0 * cos / denom } else { 0.0 }
}

/// Schlick's Fresnel approximation $F = F_0 + (1 - F_0)(1 - \cos\theta_d)^5$.
fn schlick(f0: [f64; 3], cos_d: f64) -> [f64; 3] {
    let c = (1.0 - cos_d.clamp(0.0, 1.0)).powi(5);
    [f0[0] + (1.0 - f0[0]) * c, f0[1] + (1.0 - f0[1]) * c, f0[2] + (1.0 - f0[2]) * c]
}

impl Analytic {
    /// The BRDF $f_r(\omega_l, \omega_v)$.
    ///
    /// Zero when either direction is at or below the horizon, except for [`Analytic::Gooch`]
    /// (see its documentation).
    pub fn brdf(&self, l: DVec3, v: DVec3) -> [f64; 3] {
        if !self.is_physical() {
            if l.z <= 0.0 {
                return [0.0; 3];
            }
            // Divide the shading by $\cos\theta_l$, floored so a light on the horizon gives a
            // large but finite value instead of an infinity.
            return scale(self.shading(&Query::at(l, v)), 1.0 / l.z.max(1e-3));
        }
        let (cos_l, cos_v) = (l.z, v.z);
        if cos_l <= 0.0 || cos_v <= 0.0 {
            return [0.0; 3];
        }
        match *self {
            Analytic::Lambert { albedo } => scale(albedo, 1.0 / PI),
            Analytic::BlinnPhong { diffuse, specular, exponent } => {
                // l and v are both above the horizon, so l + v != 0 and h is well defined.
                let h = (l + v).normalize();
                let n_dot_h = h.z.max(0.0);
                let lobe = (exponent + 8.0) / (8.0 * PI) * n_dot_h.powf(exponent);
                add(scale(diffuse, 1.0 / PI), scale(specular, lobe))
            }
            Analytic::Ggx { diffuse, f0, roughness } => {
                let alpha = roughness * roughness;
                let h = (l + v).normalize();
                let d = ggx_d(h.z, alpha);
                let f = schlick(f0, l.dot(h));
                let g = ggx_g1(cos_l, alpha) * ggx_g1(cos_v, alpha);
                // Both cosines are > 0 here, so the denominator is positive.
                let spec = d * g / (4.0 * cos_l * cos_v);
                add(scale(diffuse, 1.0 / PI), scale(f, spec))
            }
            Analytic::Ward { diffuse, specular, alpha } => {
                let h = (l + v).normalize();
                // $\tan^2\theta_h = (1 - \cos^2\theta_h)/\cos^2\theta_h$. With both directions
                // above the horizon $h_z > 0$; the floor keeps the exponent finite anyway.
                let c2 = (h.z * h.z).max(1e-300);
                let tan2 = (1.0 - c2).max(0.0) / c2;
                // alpha = 0 would be a mirror (a delta); floor it to keep the model finite.
                let a2 = (alpha * alpha).max(1e-12);
                let lobe = (-tan2 / a2).exp() / (4.0 * PI * a2 * (cos_l * cos_v).sqrt());
                add(scale(diffuse, 1.0 / PI), scale(specular, lobe))
            }
            Analytic::OrenNayar { albedo, sigma } => {
                let s2 = sigma * sigma;
                let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
                let b = 0.45 * s2 / (s2 + 0.09);
                // $\cos(\phi_l - \phi_v)$ from the projections onto the tangent plane. When a
                // direction is the normal its azimuth is undefined; the term is then
                // multiplied by $\sin 0 = 0$ or $\tan 0 = 0$, so any value works: use 0.
                let (pl, pv) = (l.x.hypot(l.y), v.x.hypot(v.y));
                let cos_phi = if pl > 1e-12 && pv > 1e-12 {
                    ((l.x * v.x + l.y * v.y) / (pl * pv)).clamp(-1.0, 1.0)
                } else {
                    0.0
                };
                let (theta_l, theta_v) = (cos_l.min(1.0).acos(), cos_v.min(1.0).acos());
                let (alpha, beta) = (theta_l.max(theta_v), theta_l.min(theta_v));
                // beta <= alpha <= pi/2 and beta < pi/2 strictly (both cosines > 0), so
                // tan(beta) is finite.
                let term = a + b * cos_phi.max(0.0) * alpha.sin() * beta.tan();
                scale(albedo, term / PI)
            }
            Analytic::Minnaert { albedo, k } => {
                // Both cosines are > 0, so the power is finite for any k.
                scale(albedo, (cos_l * cos_v).powf(k - 1.0) / PI)
            }
            Analytic::Phong { diffuse, specular, exponent } => {
                // $\mathbf r \cdot \mathbf v = 2 (\mathbf n\cdot\mathbf l)(\mathbf n\cdot\mathbf v)
                // - \mathbf l\cdot\mathbf v$: symmetric in l and v, hence reciprocal.
                let r_dot_v = (2.0 * cos_l * cos_v - l.dot(v)).max(0.0);
                let lobe = (exponent + 2.0) / (2.0 * PI) * r_dot_v.powf(exponent);
                add(scale(diffuse, 1.0 / PI), scale(specular, lobe))
            }
            Analytic::AshikhminShirley { diffuse, specular, exponent } => {
                let h = (l + v).normalize();
                // $\mathbf h\cdot\mathbf l = \cos\theta_d = |l + v|/2 > 0$ for directions above
                // the horizon; the floor only keeps a degenerate input finite.
                let h_dot_l = l.dot(h).max(1e-12);
                let lobe = (exponent + 1.0) / (8.0 * PI) * h.z.max(0.0).powf(exponent) / (h_dot_l * cos_l.max(cos_v));
                let spec = scale(schlick(specular, h_dot_l), lobe);
                let grazing = |c: f64| 1.0 - (1.0 - c / 2.0).powi(5);
                let d = 28.0 / (23.0 * PI) * grazing(cos_l) * grazing(cos_v);
                let diff = [0, 1, 2].map(|c| diffuse[c] * (1.0 - specular[c]) * d);
                add(diff, spec)
            }
            Analytic::Velvet { diffuse, sheen, roughness } => {
                let h = (l + v).normalize();
                let sin_h = (1.0 - h.z * h.z).max(0.0).sqrt();
                let inv_r = 1.0 / roughness.max(1e-3);
                let d = (2.0 + inv_r) * sin_h.powf(inv_r) / (2.0 * PI);
                // $c_l + c_v - c_l c_v \ge \max(c_l, c_v) > 0$ for both cosines in (0, 1].
                let vis = 1.0 / (4.0 * (cos_l + cos_v - cos_l * cos_v));
                add(scale(diffuse, 1.0 / PI), scale(sheen, d * vis))
            }
            Analytic::Gooch { .. } | Analytic::GoochSpecular { .. } => unreachable!("handled above"),
        }
    }

    /// A short descriptive name, e.g. `blinn-phong-32` or `ggx-0.4`.
    pub fn name(&self) -> String {
        match self {
            Analytic::Lambert { .. } => "lambert".into(),
            Analytic::BlinnPhong { exponent, .. } => format!("blinn-phong-{exponent}"),
            Analytic::Ggx { roughness, .. } => format!("ggx-{}", short(*roughness)),
            Analytic::Ward { alpha, .. } => format!("ward-{alpha}"),
            Analytic::OrenNayar { sigma, .. } => format!("oren-nayar-{sigma}"),
            Analytic::Minnaert { k, .. } => format!("minnaert-{k}"),
            Analytic::Gooch { .. } => "gooch".into(),
            Analytic::Phong { exponent, .. } => format!("phong-{exponent}"),
            Analytic::AshikhminShirley { exponent, .. } => format!("ashikhmin-shirley-{exponent}"),
            Analytic::Velvet { roughness, .. } => format!("velvet-{roughness}"),
            Analytic::GoochSpecular { .. } => "gooch-specular".into(),
        }
    }

    /// Whether this is a physical BRDF (reciprocal, energy conserving). False only for Gooch.
    pub fn is_physical(&self) -> bool {
        !matches!(self, Analytic::Gooch { .. } | Analytic::GoochSpecular { .. })
    }

    /// The standard evaluation suite: Lambert; Blinn-Phong with exponents 8, 32, 128; GGX with
    /// roughness 0.2, 0.4, 0.7; Ward; Oren-Nayar; Minnaert; Gooch.
    ///
    /// Colours differ per channel so that channel mix-ups show, and each physical model's
    /// diffuse plus specular reflectance stays below 1.
    pub fn suite() -> Vec<Analytic> {
        let diffuse = [0.45, 0.25, 0.12];
        let specular = [0.30, 0.35, 0.40];
        let mut out = vec![Analytic::Lambert { albedo: [0.70, 0.45, 0.20] }];
        for exponent in [8.0, 32.0, 128.0] {
            out.push(Analytic::BlinnPhong { diffuse, specular, exponent });
        }
        for roughness in [0.2, 0.4, 0.7] {
            out.push(Analytic::Ggx { diffuse: [0.40, 0.25, 0.12], f0: [0.50, 0.42, 0.35], roughness });
        }
        out.push(Analytic::Ward { diffuse: [0.20, 0.35, 0.50], specular: [0.15, 0.12, 0.10], alpha: 0.2 });
        out.push(Analytic::OrenNayar { albedo: [0.60, 0.40, 0.30], sigma: 0.5 });
        out.push(Analytic::Minnaert { albedo: [0.40, 0.15, 0.35], k: 0.75 });
        out.push(Analytic::Gooch { warm: [0.90, 0.60, 0.20], cool: [0.10, 0.20, 0.60] });
        out
    }

    /// The wide suite of issue 15: [`Analytic::suite`] plus Phong with exponents 10, 50, 200;
    /// Blinn-Phong 200; GGX with $\alpha = 0.1$ (roughness $\sqrt{0.1}$); Ward with
    /// $\alpha$ = 0.1 and 0.4; Ashikhmin-Shirley with $n$ = 10, 100, 1000; velvet with sheen;
    /// Gooch with a highlight. (Oren-Nayar $\sigma = 0.5$, also in the list, is in
    /// the base suite already: 23 models in all.)
    pub fn wide_suite() -> Vec<Analytic> {
        let diffuse = [0.45, 0.25, 0.12];
        let specular = [0.30, 0.35, 0.40];
        let mut out = Analytic::suite();
        for exponent in [10.0, 50.0, 200.0] {
            out.push(Analytic::Phong { diffuse: [0.35, 0.30, 0.15], specular, exponent });
        }
        out.push(Analytic::BlinnPhong { diffuse, specular, exponent: 200.0 });
        out.push(Analytic::ggx_alpha([0.40, 0.25, 0.12], [0.50, 0.42, 0.35], 0.1));
        for alpha in [0.1, 0.4] {
            out.push(Analytic::Ward { diffuse: [0.20, 0.35, 0.50], specular: [0.15, 0.12, 0.10], alpha });
        }
        for exponent in [10.0, 100.0, 1000.0] {
            out.push(Analytic::AshikhminShirley { diffuse: [0.50, 0.30, 0.15], specular: [0.10, 0.12, 0.15], exponent });
        }
        out.push(Analytic::Velvet { diffuse: [0.30, 0.05, 0.12], sheen: [0.60, 0.35, 0.50], roughness: 0.35 });
        out.push(Analytic::GoochSpecular {
            warm: [0.80, 0.55, 0.20],
            cool: [0.10, 0.20, 0.55],
            specular: [0.20, 0.20, 0.20],
            exponent: 60.0,
        });
        out
    }

    /// GGX by its distribution width $\alpha$ (= roughness²).
    pub fn ggx_alpha(diffuse: [f64; 3], f0: [f64; 3], alpha: f64) -> Analytic {
        Analytic::Ggx { diffuse, f0, roughness: alpha.sqrt() }
    }
}

/// A parameter for a name: at most four decimals, trailing zeros dropped (0.2 is written
/// "0.2", $\sqrt{0.1}$ "0.3162").
fn short(x: f64) -> String {
    let s = format!("{x:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

impl Reflectance for Analytic {
    /// The shading function $S = f_r \cos\theta_l$ a painting shows.
    ///
    /// For [`Analytic::Gooch`] it is
    /// $S = \mathrm{mix}(\text{cool}, \text{warm}, (1 + l_z)/2)$ on the whole sphere.
    fn shading(&self, q: &Query) -> [f64; 3] {
        let (l, v) = (q.l, q.v);
        if let Analytic::Gooch { warm, cool } = *self {
            let t = ((1.0 + l.z) * 0.5).clamp(0.0, 1.0);
            return add(scale(cool, 1.0 - t), scale(warm, t));
        }
        if let Analytic::GoochSpecular { warm, cool, specular, exponent } = *self {
            let t = ((1.0 + l.z) * 0.5).clamp(0.0, 1.0);
            let base = add(scale(cool, 1.0 - t), scale(warm, t));
            // The highlight fades out at the terminator ($l_z \to 0$), so S stays continuous.
            let highlight = q.h().z.max(0.0).powf(exponent) * l.z.max(0.0);
            return add(base, scale(specular, highlight));
        }
        let f = self.brdf(l, v);
        let c = l.z.max(0.0);
        [f[0] * c, f[1] * c, f[2] * c]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A uniformly distributed direction on the upper hemisphere.
    fn upper(rng: &mut ChaCha8Rng) -> DVec3 {
        let z: f64 = rng.random_range(0.02..1.0);
        let phi: f64 = rng.random_range(0.0..2.0 * PI);
        let r = (1.0 - z * z).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    fn dir(theta_deg: f64, phi_deg: f64) -> DVec3 {
        let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
        DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
    }

    fn close(a: [f64; 3], b: [f64; 3], rel: f64) -> bool {
        (0..3).all(|c| (a[c] - b[c]).abs() <= rel * a[c].abs().max(b[c].abs()).max(1e-12))
    }

    #[test]
    fn lambert_is_albedo_over_pi_everywhere() {
        let m = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for _ in 0..100 {
            let (l, v) = (upper(&mut rng), upper(&mut rng));
            let f = m.brdf(l, v);
            assert!(close(f, [0.7 / PI, 0.45 / PI, 0.2 / PI], 1e-14), "l={l} v={v} f={f:?}");
            let s = m.shading(&Query::at(l, v));
            assert!(close(s, scale(f, l.z), 1e-14), "l={l} v={v} s={s:?}");
        }
    }

    #[test]
    fn below_horizon_is_zero() {
        let down = dir(100.0, 0.0);
        let up = dir(30.0, 40.0);
        for m in Analytic::suite() {
            assert_eq!(m.brdf(down, up), [0.0; 3], "{}", m.name());
            if m.is_physical() {
                assert_eq!(m.brdf(up, down), [0.0; 3], "{}", m.name());
            }
        }
    }

    #[test]
    fn blinn_phong_at_normal_incidence() {
        // l = v = n gives h = n, so the lobe is (n+8)/(8 pi).
        let n = DVec3::Z;
        let m = Analytic::BlinnPhong { diffuse: [0.1, 0.2, 0.3], specular: [0.3, 0.2, 0.1], exponent: 32.0 };
        let lobe = 40.0 / (8.0 * PI);
        let want = [0.1 / PI + 0.3 * lobe, 0.2 / PI + 0.2 * lobe, 0.3 / PI + 0.1 * lobe];
        assert!(close(m.brdf(n, n), want, 1e-14), "{:?} vs {want:?}", m.brdf(n, n));
    }

    #[test]
    fn ggx_d_at_normal_is_one_over_pi_alpha_squared() {
        for alpha in [0.04, 0.16, 0.49, 1.0] {
            let d = ggx_d(1.0, alpha);
            let want = 1.0 / (PI * alpha * alpha);
            assert!((d - want).abs() <= 1e-12 * want, "alpha={alpha}: D={d}, want {want}");
        }
        // The full model at l = v = n: F = f0, G = 1 (G1(1) = 2/(1+1)), so
        // f = kd/pi + f0 / (4 pi alpha^2).
        let m = Analytic::Ggx { diffuse: [0.1, 0.2, 0.3], f0: [0.9, 0.5, 0.04], roughness: 0.4 };
        let a2 = 0.16f64 * 0.16;
        let want = [0.1 / PI + 0.9 / (4.0 * PI * a2), 0.2 / PI + 0.5 / (4.0 * PI * a2), 0.3 / PI + 0.04 / (4.0 * PI * a2)];
        let got = m.brdf(DVec3::Z, DVec3::Z);
        assert!(close(got, want, 1e-12), "{got:?} vs {want:?}");
    }

    #[test]
    fn ward_oren_nayar_minnaert_hand_values() {
        // Ward at l = v = n: tan(theta_h) = 0, so f = kd/pi + ks/(4 pi a^2).
        let m = Analytic::Ward { diffuse: [0.2, 0.0, 0.0], specular: [0.1, 0.1, 0.1], alpha: 0.2 };
        let got = m.brdf(DVec3::Z, DVec3::Z)[0];
        let want = 0.2 / PI + 0.1 / (4.0 * PI * 0.04);
        assert!((got - want).abs() < 1e-12 * want, "{got} vs {want}");
        // Oren-Nayar with sigma = 0 is Lambert.
        let on = Analytic::OrenNayar { albedo: [0.5, 0.4, 0.3], sigma: 0.0 };
        let (l, v) = (dir(60.0, 0.0), dir(45.0, 10.0));
        assert!(close(on.brdf(l, v), [0.5 / PI, 0.4 / PI, 0.3 / PI], 1e-14));
        // Oren-Nayar with l, v in the same plane, same side: A + B sin(60) tan(45).
        let on = Analytic::OrenNayar { albedo: [1.0, 1.0, 1.0], sigma: 0.5 };
        let (l, v) = (dir(60.0, 0.0), dir(45.0, 0.0));
        let (a, b) = (1.0 - 0.5 * 0.25 / 0.58, 0.45 * 0.25 / 0.34);
        let want = (a + b * 60f64.to_radians().sin() * 1.0) / PI;
        let got = on.brdf(l, v)[0];
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        // Minnaert with k = 1 is Lambert; with k = 0.5 at cos = 0.5, 0.5: (0.25)^-0.5 = 2.
        let mi = Analytic::Minnaert { albedo: [0.3, 0.3, 0.3], k: 0.5 };
        let (l, v) = (dir(60.0, 0.0), dir(60.0, 90.0));
        let got = mi.brdf(l, v)[0];
        assert!((got - 0.6 / PI).abs() < 1e-12, "{got}");
    }

    #[test]
    fn gooch_unlit_side_is_cool_and_lit_pole_is_warm() {
        let warm = [0.9, 0.6, 0.2];
        let cool = [0.1, 0.2, 0.6];
        let g = Analytic::Gooch { warm, cool };
        let v = DVec3::Z;
        assert!(close(g.shading(&Query::at(-DVec3::Z, v)), cool, 1e-14), "{:?}", g.shading(&Query::at(-DVec3::Z, v)));
        assert!(close(g.shading(&Query::at(DVec3::Z, v)), warm, 1e-14));
        let mid = g.shading(&Query::at(DVec3::X, v));
        assert!(close(mid, [0.5, 0.4, 0.4], 1e-14), "{mid:?}");
        assert_eq!(g.brdf(-DVec3::Z, v), [0.0; 3]);
        // brdf * cos reproduces the shading on the lit side.
        let l = dir(50.0, 20.0);
        assert!(close(scale(g.brdf(l, v), l.z), g.shading(&Query::at(l, v)), 1e-12));
        assert!(!g.is_physical());
    }

    #[test]
    fn physical_models_are_reciprocal_and_non_negative() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for m in Analytic::wide_suite().into_iter().filter(Analytic::is_physical) {
            for _ in 0..2000 {
                let (l, v) = (upper(&mut rng), upper(&mut rng));
                let (a, b) = (m.brdf(l, v), m.brdf(v, l));
                assert!(a.iter().all(|x| x.is_finite() && *x >= 0.0), "{}: l={l} v={v} f={a:?}", m.name());
                assert!(close(a, b, 1e-10), "{}: f(l,v)={a:?} f(v,l)={b:?} l={l} v={v}", m.name());
            }
        }
    }

    #[test]
    fn gooch_shading_is_finite_and_non_negative_everywhere() {
        let g = Analytic::suite().pop().unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for _ in 0..1000 {
            let mut l = upper(&mut rng);
            if rng.random::<bool>() {
                l.z = -l.z;
            }
            let s = g.shading(&Query::at(l, DVec3::Z));
            assert!(s.iter().all(|x| x.is_finite() && *x >= 0.0), "l={l} s={s:?}");
            let f = g.brdf(l, DVec3::Z);
            assert!(f.iter().all(|x| x.is_finite() && *x >= 0.0), "l={l} f={f:?}");
        }
    }

    /// Directional albedo $\int f \cos\theta_l\,d\omega_l$ by jittered stratified sampling of
    /// the hemisphere, uniform in $(\cos\theta, \phi)$ (solid angle $2\pi$).
    fn directional_albedo(m: &Analytic, v: DVec3, rng: &mut ChaCha8Rng) -> [f64; 3] {
        let n = 400;
        let mut sum = [0.0; 3];
        for i in 0..n {
            for j in 0..n {
                let z = (i as f64 + rng.random::<f64>()) / n as f64;
                let phi = 2.0 * PI * (j as f64 + rng.random::<f64>()) / n as f64;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let l = DVec3::new(r * phi.cos(), r * phi.sin(), z);
                sum = add(sum, m.shading(&Query::at(l, v)));
            }
        }
        scale(sum, 2.0 * PI / (n * n) as f64)
    }

    #[test]
    fn physical_models_conserve_energy() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let sharp = Analytic::ggx_alpha([0.4, 0.25, 0.12], [0.5, 0.42, 0.35], 0.05);
        for m in Analytic::wide_suite().into_iter().chain([sharp]).filter(Analytic::is_physical) {
            for theta_v in [0.0, 30.0, 60.0, 75.0] {
                let v = dir(theta_v, 25.0);
                let a = directional_albedo(&m, v, &mut rng);
                assert!(a.iter().all(|x| *x <= 1.02), "{}: theta_v={theta_v}: albedo {a:?}", m.name());
                assert!(a.iter().all(|x| *x > 0.0), "{}: theta_v={theta_v}: albedo {a:?}", m.name());
            }
        }
        // Sanity of the estimator itself: Lambert's directional albedo is its albedo.
        let m = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
        let a = directional_albedo(&m, DVec3::Z, &mut rng);
        assert!(close(a, [0.7, 0.45, 0.2], 2e-3), "{a:?}");
    }

    #[test]
    fn phong_ashikhmin_shirley_velvet_hand_values() {
        // Phong in the mirror direction: r = v, so the lobe is (n+2)/(2 pi).
        let m = Analytic::Phong { diffuse: [0.1, 0.0, 0.0], specular: [0.3, 0.3, 0.3], exponent: 50.0 };
        let (l, v) = (dir(40.0, 0.0), dir(40.0, 180.0));
        let want = 0.1 / PI + 0.3 * 52.0 / (2.0 * PI);
        assert!((m.brdf(l, v)[0] - want).abs() < 1e-12 * want, "{:?} vs {want}", m.brdf(l, v));
        // 90 degrees off the mirror direction: cos^50 of 0 is 0, only the diffuse is left.
        let v = dir(50.0, 0.0);
        assert!((m.brdf(l, v)[0] - 0.1 / PI).abs() < 1e-12);
        // Ashikhmin-Shirley at l = v = n: h = n, h.l = 1, F = Rs;
        // f = (n+1)/(8 pi) Rs + 28/(23 pi) Rd (1 - Rs) (1 - 2^-5)^2.
        let m = Analytic::AshikhminShirley { diffuse: [0.5, 0.5, 0.5], specular: [0.1, 0.1, 0.1], exponent: 100.0 };
        let want = 101.0 / (8.0 * PI) * 0.1 + 28.0 / (23.0 * PI) * 0.5 * 0.9 * (1.0 - 1.0 / 32.0f64).powi(2);
        let got = m.brdf(DVec3::Z, DVec3::Z)[0];
        assert!((got - want).abs() < 1e-12 * want, "{got} vs {want}");
        // Velvet facing the light and viewer: sin(theta_h) = 0, no sheen, only the diffuse.
        let m = Analytic::Velvet { diffuse: [0.3, 0.0, 0.0], sheen: [0.6, 0.6, 0.6], roughness: 0.35 };
        assert!((m.brdf(DVec3::Z, DVec3::Z)[0] - 0.3 / PI).abs() < 1e-12);
        // With h on the horizon-ish: l, v at 80 degrees on opposite sides gives h = n again;
        // on the same side (l = v at 80 degrees) h = l, sin = sin 80, V = 1/(4(2c - c^2)).
        let l = dir(80.0, 0.0);
        let (c, sn) = (80f64.to_radians().cos(), 80f64.to_radians().sin());
        let inv_r = 1.0 / 0.35;
        let d = (2.0 + inv_r) * sn.powf(inv_r) / (2.0 * PI);
        let want = 0.6 * d / (4.0 * (2.0 * c - c * c));
        assert!((m.brdf(l, l)[1] - want).abs() < 1e-12 * want, "{:?} vs {want}", m.brdf(l, l));
    }

    #[test]
    fn gooch_specular_adds_a_highlight_that_fades_at_the_terminator() {
        let m = Analytic::GoochSpecular { warm: [0.8, 0.5, 0.2], cool: [0.1, 0.2, 0.5], specular: [0.2; 3], exponent: 60.0 };
        // l = v = n: h = n, the full highlight on the warm pole.
        let s = m.shading(&Query::at(DVec3::Z, DVec3::Z));
        assert!(close(s, [1.0, 0.7, 0.4], 1e-12), "{s:?}");
        // On the terminator the highlight is gone whatever h is: mix at t = 1/2.
        let s = m.shading(&Query::at(DVec3::X, dir(0.0, 0.0)));
        assert!(close(s, [0.45, 0.35, 0.35], 1e-12), "{s:?}");
        assert!(!m.is_physical());
    }

    #[test]
    fn wide_suite_names_are_distinct() {
        let names: Vec<String> = Analytic::wide_suite().iter().map(Analytic::name).collect();
        let mut sorted = names.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), names.len(), "{names:?}");
        assert_eq!(names.len(), 23);
        assert!(names.contains(&"ggx-0.3162".to_string()) && names.contains(&"ashikhmin-shirley-1000".to_string()), "{names:?}");
    }

    #[test]
    fn names_are_distinct() {
        let names: Vec<String> = Analytic::suite().iter().map(Analytic::name).collect();
        let mut sorted = names.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), names.len(), "{names:?}");
        assert!(names.contains(&"blinn-phong-32".to_string()), "{names:?}");
        assert_eq!(names.len(), 11);
    }
}
