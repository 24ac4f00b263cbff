//! The lobe model of the analytic base under the factored product: one vocabulary of
//! classic families, evaluated here for the CPU (the material's base, the fit) and in
//! `shaders/term.glsl` for the GPU (tests/render_material.rs holds the two together).
//!
//! The lobe, per colour channel $c$, in the local frame ($\cos\theta = z$):
//! $$ B_c = a_c + \cos^+\theta_l\,\Big(k_{d,c} + \big(k_{s,c} + k_{f,c}(1 - \cos\theta_d)^5\big)
//!    \frac{D(\theta_h; \alpha)\, G_1(\theta_l)\,G_1(\theta_v)}{4\cos\theta_l\cos\theta_v}\Big) $$
//! with GGX's $D$ and Smith's $G_1$, or, in place of that microfacet lobe, the lobe of
//! another classic family ([`Lobe`]: Blinn-Phong, Phong, Ward, Ashikhmin-Shirley, whose
//! diffuse shape replaces $\cos^+\theta_l$ too, and the rough-diffuse terms of Oren-Nayar
//! and Minnaert), each with at most one width $\alpha$. Schlick's Fresnel $F = F_0 + (1 -
//! F_0)(1 - \cos\theta_d)^5$ times a scale $k$ is $k_s + k_f (1 - \cos\theta_d)^5$ with
//! $k_s = k F_0$, $k_f = k(1 - F_0)$: linear in both, so every channel has its own $F_0$.
//! Fitting a lobe to samples: [`super::lobe_fit`].

use std::f64::consts::PI;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::factor::Query;

/// Schlick's $F_0$ of a dielectric of index of refraction 1.5, $((1.5 - 1)/(1.5 + 1))^2$:
/// plastics, paint binders, varnish and glass (1.46–1.6), and glTF's dielectric.
pub const DIELECTRIC_F0: f64 = 0.04;

/// An analytic lobe under the factors. See the module documentation for the formula.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Base {
    /// Ambient $a$, per channel.
    pub ambient: [f64; 3],
    /// Diffuse $k_d$ (of the shading: $k_d \cos\theta_l$; a Lambertian albedo is $\pi k_d$).
    pub diffuse: [f64; 3],
    /// Specular $k_s$, the colour of the lobe at normal incidence (Schlick's $k F_0$).
    pub specular: [f64; 3],
    /// Fresnel $k_f$, what grazing $\theta_d$ adds (Schlick's $k (1 - F_0)$); 0 for none.
    pub fresnel: [f64; 3],
    /// The lobe's width $\alpha \in (0, 1]$: GGX's and Ward's $\alpha$, the Blinn-Phong,
    /// Phong and Ashikhmin-Shirley exponent through [`Lobe::exponent`], Minnaert's $k$;
    /// unused by Oren-Nayar (1).
    pub alpha: f64,
    /// The specular lobe's family (GGX unless told: version 3 files have only GGX).
    #[serde(default)]
    pub lobe: Lobe,
}

/// GGX's $D(\theta_h) = \alpha^2 / (\pi((\alpha^2 - 1)\cos^2\theta_h + 1)^2)$: the one
/// definition, shared by the analytic GGX model ([`super::Analytic`]).
pub(crate) fn ggx_d(cos_h: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let t = (a2 - 1.0) * cos_h * cos_h + 1.0;
    // t >= min(a2, 1) > 0 for alpha > 0; the floor only guards alpha = 0 (a mirror), where
    // D is a delta function no table holds.
    a2 / (PI * (t * t).max(1e-300))
}

/// Smith's $G_1$ for GGX, divided by $2\cos\theta$: $1/(\cos\theta + \sqrt{\alpha^2 + (1 -
/// \alpha^2)\cos^2\theta})$. Dividing out the cosine keeps the lobe finite at grazing angles
/// where $G_1/\cos\theta$ is, and saves the division by $4\cos\theta_l\cos\theta_v$.
fn g1_over_2cos(cos: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    1.0 / (cos + (a2 + (1.0 - a2) * cos * cos).sqrt())
}

/// The lobe's specular shading at unit $k_s$, $s = \cos\theta_l\, D\, G_1 G_1 / (4
/// \cos\theta_l \cos\theta_v)$, and Schlick's $(1 - \cos\theta_d)^5$; both zero when
/// either direction is at or below the horizon.
pub fn specular_shape(l: DVec3, v: DVec3, alpha: f64) -> (f64, f64) {
    let (cl, cv) = (l.z, v.z);
    if cl <= 0.0 || cv <= 0.0 {
        return (0.0, 0.0);
    }
    // Both above the horizon, so l + v != 0.
    let h = (l + v).normalize();
    let x = 1.0 - l.dot(h).clamp(0.0, 1.0);
    // $\cos\theta_l \cdot D \cdot \frac{G_1(l)}{2 c_l} \frac{G_1(v)}{2 c_v}$.
    (cl * ggx_d(h.z, alpha) * g1_over_2cos(cl, alpha) * g1_over_2cos(cv, alpha), x.powi(5))
}

/// The family of a base's lobe. One width $\alpha \in (0, 1]$ serves every family that has
/// one: the Blinn-Phong, Phong and Ashikhmin-Shirley exponents are $e = 2/\alpha^2 - 2$, the
/// usual correspondence of a Blinn-Phong lobe with a Beckmann (and, near its peak, GGX) lobe
/// of width $\alpha$; Minnaert's $k$ is $\alpha$; Oren-Nayar has none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Lobe {
    /// The microfacet lobe of the module documentation (GGX, Smith masking).
    #[default]
    Ggx,
    /// $\cos\theta_l\,(\mathbf n\cdot\mathbf h)^e$: the Blinn-Phong highlight, no masking
    /// and no $1/\cos$ rise at grazing angles.
    BlinnPhong,
    /// $\cos\theta_l\,\max(0, \mathbf r\cdot\mathbf v)^e$ with $\mathbf r$ the mirror of
    /// $\mathbf l$: Phong's highlight, which no table of $\theta_h$ holds (its isophotes are
    /// circles about the mirror direction, not about $\mathbf n$).
    Phong,
    /// Isotropic Ward (1992): $\cos\theta_l\, e^{-\tan^2\theta_h/\alpha^2} / (4\pi\alpha^2
    /// \sqrt{\cos\theta_l\cos\theta_v})$, a Gaussian highlight with a milder rise at
    /// grazing angles than the microfacet lobe's.
    Ward,
    /// Isotropic Ashikhmin-Shirley (2000): $\cos\theta_l\,(\mathbf n\cdot\mathbf h)^e /
    /// ((\mathbf h\cdot\mathbf l)\max(\cos\theta_l, \cos\theta_v))$, with its own diffuse
    /// shape in place of Lambert's, $\cos\theta_l\, g(\cos\theta_l)\, g(\cos\theta_v)$, $g(c)
    /// = 1 - (1 - c/2)^5$ (its Schlick Fresnel is the linear $k_s + k_f x^5$ as for the
    /// others, pulled to its own $F_0 = R_s$ where the data do not decide, [`super::lobe_fit`];
    /// its $(1 - R_s)$ is in $k_d$).
    AshikhminShirley,
    /// Oren-Nayar's rough diffuse (qualitative model, 1994): Lambert ($k_d$, their $A$) plus
    /// $\cos\theta_l \max(0, \cos(\phi_l - \phi_v)) \sin\max(\theta_l, \theta_v)
    /// \tan\min(\theta_l, \theta_v)$ (their $B$ term, as $k_s$): the retro-reflection of
    /// clay, plaster and cloth. No width: $\sigma$ is in the ratio of the two coefficients.
    OrenNayar,
    /// Minnaert's limb darkening (1941): $\cos\theta_l\,(\cos\theta_l\cos\theta_v)^{k - 1}$
    /// with $k = \alpha$ (1 is Lambert), for the moon's flat disk and velvet.
    Minnaert,
}

impl Lobe {
    /// Every family, in the order a fit tries them (the first wins a tie).
    pub const ALL: [Lobe; 7] = [Lobe::Ggx, Lobe::BlinnPhong, Lobe::Phong, Lobe::Ward, Lobe::AshikhminShirley, Lobe::OrenNayar, Lobe::Minnaert];

    /// The name in `material.json` and in `fit`'s output.
    pub fn name(self) -> &'static str {
        match self {
            Lobe::Ggx => "ggx",
            Lobe::BlinnPhong => "blinn-phong",
            Lobe::Phong => "phong",
            Lobe::Ward => "ward",
            Lobe::AshikhminShirley => "ashikhmin-shirley",
            Lobe::OrenNayar => "oren-nayar",
            Lobe::Minnaert => "minnaert",
        }
    }

    /// The Blinn-Phong, Phong and Ashikhmin-Shirley exponent of width $\alpha$: $2/\alpha^2 - 2$.
    pub fn exponent(alpha: f64) -> f64 {
        2.0 / (alpha * alpha) - 2.0
    }

    /// Width $\alpha$ as a user reads it: the exponent, $\alpha$ or $k$ of the family.
    pub fn width_of(self, alpha: f64) -> String {
        match self {
            Lobe::BlinnPhong | Lobe::Phong | Lobe::AshikhminShirley => format!("exponent {:.1}", Lobe::exponent(alpha)),
            Lobe::Ggx | Lobe::Ward => format!("alpha {alpha:.4}"),
            Lobe::Minnaert => format!("k {alpha:.3}"),
            // σ is in the weights ([`Base::width`]).
            Lobe::OrenNayar => String::new(),
        }
    }

    /// Whether the family has a width to search (Oren-Nayar has none).
    pub fn has_width(self) -> bool {
        self != Lobe::OrenNayar
    }

    /// Whether only samples at grazing $\theta_d$ decide the lobe's Fresnel $k_f$ (the ridge
    /// holds it at 0 elsewhere, [`super::lobe_fit`]): the specular families but Ashikhmin-Shirley,
    /// whose Fresnel is its own.
    pub fn fresnel_from_data(self) -> bool {
        matches!(self, Lobe::Ggx | Lobe::BlinnPhong | Lobe::Phong | Lobe::Ward)
    }

    /// The lobe's diffuse shading at unit $k_d$ ($\cos^+\theta_l$, but for
    /// Ashikhmin-Shirley), its specular shading at unit $k_s$, and Schlick's $(1 -
    /// \cos\theta_d)^5$; the last two zero when either direction is at or below the horizon.
    pub fn shape(self, l: DVec3, v: DVec3, alpha: f64) -> (f64, f64, f64) {
        let (cl, cv) = (l.z, v.z);
        if cl <= 0.0 || cv <= 0.0 {
            // Ashikhmin-Shirley's diffuse has g(cos θ_v) = 0 at the horizon and below.
            let lambert = if self == Lobe::AshikhminShirley { 0.0 } else { cl.max(0.0) };
            return (lambert, 0.0, 0.0);
        }
        // Both above the horizon, so l + v != 0.
        let h = (l + v).normalize();
        let x5 = (1.0 - l.dot(h).clamp(0.0, 1.0)).powi(5);
        // 0 at c = 0 even for the exponent 0 of α = 1, as the shader's pow is taken.
        let power = |c: f64, e: f64| if c > 0.0 { c.powf(e) } else { 0.0 };
        let (diffuse, spec) = match self {
            Lobe::Ggx => (cl, specular_shape(l, v, alpha).0),
            Lobe::BlinnPhong => (cl, cl * power(h.z, Lobe::exponent(alpha))),
            // r.v = 2 (n.l)(n.v) - l.v (symmetric in l and v).
            Lobe::Phong => (cl, cl * power(2.0 * cl * cv - l.dot(v), Lobe::exponent(alpha))),
            Lobe::Ward => {
                // tan²θ_h = (1 - cos²)/cos²; h.z > 0 for directions above the horizon.
                let c2 = (h.z * h.z).max(1e-300);
                let a2 = alpha * alpha;
                (cl, cl * (-(1.0 - c2) / (c2 * a2)).exp() / (4.0 * PI * a2 * (cl * cv).sqrt()))
            }
            Lobe::AshikhminShirley => {
                let g = |c: f64| 1.0 - (1.0 - c / 2.0).powi(5);
                // h.l = |l + v|/2 > 0 above the horizon.
                (cl * g(cl) * g(cv), cl * power(h.z, Lobe::exponent(alpha)) / (l.dot(h).max(1e-12) * cl.max(cv)))
            }
            Lobe::OrenNayar => {
                // cos(φ_l − φ_v) from the tangent-plane projections (0 where one is the normal,
                // where the sine or tangent below is 0 anyway). θ_max has the smaller cosine:
                // sin θ_max = √(1 − c_min²), tan θ_min = √(1 − c_max²)/c_max.
                let (pl, pv) = (l.x.hypot(l.y), v.x.hypot(v.y));
                let cos_phi = if pl > 1e-12 && pv > 1e-12 { ((l.x * v.x + l.y * v.y) / (pl * pv)).max(0.0) } else { 0.0 };
                let (c_max, c_min) = (cl.max(cv), cl.min(cv));
                (cl, cl * cos_phi * (1.0 - c_min * c_min).max(0.0).sqrt() * (1.0 - c_max * c_max).max(0.0).sqrt() / c_max)
            }
            Lobe::Minnaert => (cl, cl * (cl * cv).powf(alpha - 1.0)),
        };
        (diffuse, spec, x5)
    }
}

impl Base {
    /// $B(l, v)$ per channel (see the module documentation).
    pub fn shading(&self, q: &Query) -> [f64; 3] {
        let (d, s, x5) = self.lobe.shape(q.l, q.v, self.alpha);
        [0, 1, 2].map(|c| self.ambient[c] + d * self.diffuse[c] + s * (self.specular[c] + x5 * self.fresnel[c]))
    }

    /// The lobe's width as a user reads it: the exponent of a Blinn-Phong, Phong or
    /// Ashikhmin-Shirley lobe, $\alpha$ of a GGX or Ward one, Minnaert's $k$, Oren-Nayar's
    /// $B/A$ (which says $\sigma$).
    pub fn width(&self) -> String {
        match self.lobe {
            // σ is in the ratio of the B term to the A term (Lambert).
            Lobe::OrenNayar => format!("B/A {:.3}", self.specular[1] / self.diffuse[1].max(1e-12)),
            lobe => lobe.width_of(self.alpha),
        }
    }

    /// Checks a stored lobe: colours finite and non-negative, $0 < \alpha \le 1$ (the range
    /// the fit searches; at 0 $D$ is a delta function).
    pub fn validate(&self) -> std::result::Result<(), String> {
        let colours = self.ambient.iter().chain(&self.diffuse).chain(&self.specular).chain(&self.fresnel);
        if colours.clone().any(|x| !x.is_finite() || *x < 0.0) {
            return Err("ambient, diffuse and specular must be finite and non-negative".into());
        }
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(format!("alpha {} must be in (0, 1]", self.alpha));
        }
        Ok(())
    }
}

