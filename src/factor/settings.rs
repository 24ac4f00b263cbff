//! What to fit: the factors (input, parameterization, resolution, regularization) and how to
//! solve. Together with a [`Pattern`](super::Pattern) these fix the prepared system.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::param::{Domain, Param};
use super::pattern::Query;
use crate::error::{Error, Result};

/// What a factor looks up.
#[derive(Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Input {
    /// The light direction $l$ (the thesis's $p$).
    Light,
    /// The half vector $h$ (the thesis's $q$).
    Half,
    /// The view direction $v$ (the thesis's $r$).
    View,
    /// Surface texture coordinates (the fourth factor $s(u, v)$, thesis 4.2.1).
    Uv,
    /// The difference vector $d$ of Rusinkiewicz's half/difference coordinates (1998): $l$
    /// seen from a frame whose pole is $h$, so $\cos\theta_d = l \cdot h$. With the radius
    /// map a factor of $\theta_d$, which carries Fresnel and grazing terms that depend on the
    /// angle between light and half vector rather than on $\theta_l$, $\theta_h$ or $\theta_v$.
    Difference,
    /// The pair $(h, d)$: with [`Param::Radii`] a 2D factor of $(\theta_h, \theta_d)$, the
    /// isotropic BRDF's main two coordinates (Rusinkiewicz 1998, its $\phi_d$ dropped).
    HalfDifference,
    /// A projection the caller supplies. Not storable in a material.
    Custom(CustomInput),
}

impl fmt::Debug for Input {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Input {
    /// Short name: light, half, view, uv, or the custom projection's name.
    pub fn name(&self) -> &str {
        match self {
            Input::Light => "light",
            Input::Half => "half",
            Input::View => "view",
            Input::Uv => "uv",
            Input::Difference => "difference",
            Input::HalfDifference => "half-difference",
            Input::Custom(c) => &c.name,
        }
    }
}

/// A caller-supplied projection: maps a query straight to table coordinates in $[0,1]$
/// (the second coordinate is ignored by 1D tables). The name identifies it in cache keys.
/// A custom projection of a query to table coordinates.
pub type Projection = Arc<dyn Fn(&Query) -> [f64; 2] + Send + Sync>;

#[derive(Clone)]
pub struct CustomInput {
    pub name: String,
    pub project: Projection,
}

impl PartialEq for CustomInput {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl Serialize for CustomInput {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name)
    }
}

impl<'de> Deserialize<'de> for CustomInput {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Err(serde::de::Error::custom(format!("custom projection '{name}' cannot be loaded from a file")))
    }
}

/// One factor of the product.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FactorSpec {
    pub input: Input,
    pub param: Param,
    pub domain: Domain,
    /// Table nodes per axis.
    pub res: usize,
    /// Laplacian smoothing weight $\lambda$ (eq. 3.4). Scale-free: the smoothing term is
    /// $\lambda^2 N \int |\nabla^2 \tilde p|^2$ over the table's unit domain, so one value means
    /// the same smoothness at any resolution and sample count $N$.
    pub smooth: f64,
    /// First-difference damping $\mu$: adds $\mu N \int |\nabla \tilde p|^2$, pulling the
    /// factor toward a constant wherever the data leaves it free. This is what makes a fit
    /// from one painting generalize (see [`Settings::default`]).
    pub damp: f64,
    /// Ridge $\rho$: adds $\rho N \int \tilde p^2$, pulling the factor toward 1. Used for the
    /// uv factor, which a single view could otherwise use to absorb all shading.
    pub ridge: f64,
    /// Node warp $\gamma \ge 1$ of a radius table (the first axis of [`Param::Radii`]): the
    /// table is uniform in $s = t^{1/\gamma}$ instead of the radius coordinate $t$, so nodes
    /// crowd toward $t = 0$ (with $\gamma = 3$ the first tenth of the radius holds 46% of
    /// them): a narrow highlight at $\theta_h = 0$ falls on many nodes, not two. The
    /// smoothing, damping and ridge act per unit of $s$, the table's own coordinate, so one
    /// $\lambda$ keeps its meaning: the same smoothness between neighbouring nodes. 1 (no
    /// warp) is the thesis's table and material format version 1.
    #[serde(default = "no_warp", skip_serializing_if = "is_no_warp")]
    pub warp: f64,
    /// Lean $k > 0$ of a half-vector factor's input: it looks up $h_k \propto l + k v$
    /// ([`super::leaned_half`]) instead of $h = h_1$, so a highlight a painter drew nearer the
    /// light (or the eye) than the mirror direction stays where it was drawn under every
    /// light ([`crate::litsphere::highlight_lean`]). 1 (absent) is the thesis's $q(h)$;
    /// other values are material format version 6.
    #[serde(default = "no_lean", skip_serializing_if = "is_no_lean")]
    pub lean: f64,
}

fn no_lean() -> f64 {
    1.0
}

fn is_no_lean(k: &f64) -> bool {
    *k == 1.0
}

/// Leans accepted: a highlight between the light (1/8) and the eye (8).
pub const LEAN_RANGE: std::ops::RangeInclusive<f64> = 0.125..=8.0;

fn no_warp() -> f64 {
    1.0
}

fn is_no_warp(w: &f64) -> bool {
    *w == 1.0
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// Largest node warp accepted.
pub const MAX_WARP: f64 = 8.0;

impl FactorSpec {
    /// A factor of $\theta_d$ with `res` nodes (half/difference coordinates, Rusinkiewicz
    /// 1998): the radius map of the difference vector. It is damped like $r(v)$: one painting
    /// with a distant light and camera sees a single $\theta_d$ (half the angle between
    /// them), and the damping keeps the factor constant wherever paintings leave it free.
    pub fn difference(res: usize) -> FactorSpec {
        FactorSpec {
            input: Input::Difference,
            param: Param::Radius,
            domain: Domain::Hemisphere,
            res,
            smooth: defaults::SMOOTH_1D,
            damp: defaults::DAMP_1D,
            ridge: 0.0,
            warp: 1.0,
            lean: 1.0,
        }
    }

    /// Table dimension (1 or 2).
    pub fn dim(&self) -> usize {
        self.param.dim()
    }

    /// Number of table entries.
    pub fn len(&self) -> usize {
        self.res.pow(self.dim() as u32)
    }

    /// Whether the table is empty (never, for a valid spec).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// How the prepared system is solved (thesis 3.2.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Method {
    /// Cholesky factorization of the normal equations (dense or sparse, chosen by fill).
    #[default]
    Cholesky,
    /// Truncated pseudo-inverse (eq. 3.7): singular values below `rel_tol` × the largest
    /// are dropped.
    TruncatedSvd { rel_tol: f64 },
    /// Damped pseudo-inverse (eq. 3.8) with $\alpha$ = `alpha` × the largest singular value.
    DampedSvd { alpha: f64 },
    /// Linearly damped pseudo-inverse (eq. 3.9): the $i$-th singular value (descending)
    /// is scaled by $\mathrm{pos}(1 - i\gamma)$.
    LinearSvd { gamma: f64 },
}

/// The factors and the solve method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    pub factors: Vec<FactorSpec>,
    pub method: Method,
    /// A physical prior on the light factor, where the data leave it free: its smoothing and
    /// damping rows act on its deviation from $\cos\theta_l$ (falling to this floor, times
    /// the painting's largest value, behind the surface) instead of on the factor itself, as
    /// in [`super::robust`]. Only the right-hand side changes (the prepared system does not).
    /// `None`, the default: off. Lit spheres turn it on ([`crate::litsphere::settings`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub light_prior: Option<f64>,
    /// The angular radius, degrees, of the key light whose irradiance is the light prior's
    /// shape ([`super::bound::key_irradiance`]): 0, a point light, unless the caller knows
    /// the light to be an area (a lit sphere lit by its surroundings, `litsphere::light_size`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub light_radius_deg: f64,
    /// How the colour channels are fitted ([`Channels`]): independently by default, as the
    /// thesis does; stored settings without the field read as independent too.
    #[serde(default = "Channels::thesis")]
    pub channels: Channels,
}

/// Defaults, chosen by measuring relative RMS on held-out lights and views (not on the
/// fitted samples) over the analytic suite painted on a sphere from one and from three views
/// (`cargo run --release --example conditioning -- sweep`; BENCHMARKS.md, "Conditioning").
pub mod defaults {
    /// Nodes of a 1D factor.
    pub const RES_1D: usize = 128;
    /// Nodes per axis of a 2D directional factor.
    pub const RES_2D: usize = 32;
    /// Nodes per axis of the uv factor.
    pub const RES_UV: usize = 32;
    /// Laplacian weight of 1D factors. Larger values flatten narrow highlights.
    pub const SMOOTH_1D: f64 = 1e-5;
    /// Laplacian weight of 2D factors, which have far more unknowns per sample.
    pub const SMOOTH_2D: f64 = 1e-4;
    /// Laplacian weight of the uv factor. Textures have edges: at 1e-3 the smoothing
    /// outweighed the data at a step in albedo (an albedo ratio of 2.5 between bands came
    /// out 2.35 from four views that see the whole sphere); at 1e-4 it comes out 2.45, and
    /// the held-out error of that fit drops from 0.34 to 0.15.
    pub const SMOOTH_UV: f64 = 1e-4;
    /// Laplacian weight of the uv factor in the terms of a hybrid material map, where the
    /// coefficient textures carry the texel detail and $s(u, v)$ only the slow variation: at
    /// 1e-4 it fitted the painted light too, and a striped test object's held-out error was
    /// 0.54; at 1e-3, 0.18 (a plain material map: 0.16).
    pub const SMOOTH_UV_HYBRID: f64 = 1e-3;
    /// First-difference damping of the view factor $r(v)$ for 1D factors: the weak prior
    /// that settles the near-null direction of a single view (see [`super::Settings::default`]).
    pub const DAMP_1D: f64 = 1e-4;
    /// The same for 2D factors.
    pub const DAMP_2D: f64 = 1e-5;
    /// A far weaker damping of the 2D light and half-vector factors. A 2D table has regions
    /// no sample of one view reaches; the Laplacian alone continues them linearly in log
    /// space, which is exponential growth once exponentiated (factor values of 1e10 were seen
    /// on other models). This keeps them near constant instead: held-out median from one
    /// view 0.94 → 0.43, from three 0.055 → 0.053.
    pub const DAMP_2D_FREE: f64 = 1e-7;
    /// Ridge of the uv factor.
    pub const RIDGE_UV: f64 = 1e-2;
    /// Nodes of a factor of $\theta_d$ (`fit --theta-d`): $\theta_d$ spans at most 90°, and
    /// paintings show few of its values.
    pub const RES_DIFFERENCE: usize = 32;
    /// Node warp of the 1D half-vector factor $q(h)$ ([`super::FactorSpec::warp`]): its nodes
    /// are uniform in $\tan(\theta_h/2)^{1/3}$. On the wide suite (`cargo run --release
    /// --example suite`, BENCHMARKS.md "The wide suite") against the unwarped table: median
    /// held-out error from three paintings 0.0336 → 0.0330, from one 0.0837 → 0.0843, worst
    /// held-out view from three 1.43 → 0.96 and from one 2.97 → 1.79; GGX $\alpha = 0.05$'s
    /// peak on held-out views from three paintings within 7% of the truth (unwarped: 31% too
    /// bright on one view). A warp of 2 left that peak 18% off; 4 was no better than 3.
    pub const WARP_HALF: f64 = 3.0;
    /// First-difference damping of the light factor's deviation from its physical shape
    /// when the paintings are headlit ([`super::Settings::for_pattern`]). Chosen on the
    /// faults study's headlit paintings (`cargo run --release --example faults -- --read
    /// --front`; BENCHMARKS.md, "Headlit paintings"): at 1e-5 the worst held-out view with
    /// every fault was 0.64, at 1e-4 0.42, at 1e-3 0.55 (before the headlit lobes' ambient
    /// rule, `base::HEADLIT_AMBIENT_GAIN`).
    pub const DAMP_HEADLIT: f64 = 1e-4;
    /// The light prior's floor behind the surface, a fraction of the painting's largest
    /// value ([`super::Settings::light_prior`]).
    pub const LIGHT_FLOOR: f64 = 0.02;
}

/// Largest table resolution per axis accepted for 1D and 2D factors.
pub const MAX_RES_1D: usize = 1 << 14;
pub const MAX_RES_2D: usize = 1024;
/// Largest total number of unknowns.
pub const MAX_UNKNOWNS: usize = 1 << 20;

impl Default for Settings {
    /// The thesis's isotropic product $p(l)\,q(h)\,r(v)$ with 1D radius factors (eq. 3.5).
    ///
    /// Conditioning: on one painted view, $\cos\theta_h$ is nearly a function of
    /// $\cos\theta_l$ and $\cos\theta_v$ (exactly, for a distant light and camera:
    /// $\cos\theta_h = (\cos\theta_l + \cos\theta_v) / (2\cos(\alpha/2))$), so a log-space
    /// change $k(\cos\theta_l + \cos\theta_v - 2\cos(\alpha/2)\cos\theta_h)$ spread over the
    /// three factors leaves the painting unchanged and ruins every other view. The data says
    /// nothing about that direction, so any prior settles it; a weak first-difference damping
    /// of the view factor $r$ alone (the light and half-vector factors stay free) settles it
    /// in favour of BRDFs that vary little with the view direction once $h$ and $l$ are
    /// known, which held-out measurement favours over the alternatives (damping $q$ too, or
    /// a stronger Laplacian). A Lambertian or Blinn-Phong painting then gives a constant $r$.
    ///
    /// The half-vector table's nodes are warped toward $\theta_h = 0$ ([`defaults::WARP_HALF`]),
    /// so a narrow highlight falls on many nodes.
    fn default() -> Self {
        Settings::uniform(1, defaults::RES_1D)
    }
}

impl Settings {
    /// Three factors $p(l)\,q(h)\,r(v)$: 1D radius factors (`dim` = 1), the half-vector
    /// factor's nodes warped toward $\theta_h = 0$ ([`defaults::WARP_HALF`]), or 2D parabolic
    /// ones.
    pub fn uniform(dim: usize, res: usize) -> Settings {
        let (param, smooth, damp, free) = if dim == 1 {
            (Param::Radius, defaults::SMOOTH_1D, defaults::DAMP_1D, 0.0)
        } else {
            (Param::Parabolic, defaults::SMOOTH_2D, defaults::DAMP_2D, defaults::DAMP_2D_FREE)
        };
        let factor = |input, domain, damp| FactorSpec { input, param, domain, res, smooth, damp, ridge: 0.0, warp: 1.0, lean: 1.0 };
        let mut half = factor(Input::Half, if dim == 1 { Domain::Sphere } else { Domain::Hemisphere }, free);
        if dim == 1 {
            half.warp = defaults::WARP_HALF;
        }
        // 2D tables spend a quarter of their area on the lower hemisphere in the sphere
        // domain, so only the light factor (the unlit side) gets it there (`half` above).
        Settings {
            factors: vec![
                factor(Input::Light, Domain::Sphere, free),
                half,
                factor(Input::View, Domain::Hemisphere, damp),
            ],
            method: Method::Cholesky,
            light_prior: None,
            light_radius_deg: 0.0,
            channels: Channels::default(),
        }
    }

    /// The four-factor product $p(l)\,q(h)\,r(v)\,s(u,v)$ (thesis 4.2.1).
    pub fn four_factor(dim: usize, res: usize, uv_res: usize) -> Settings {
        let mut s = Settings::uniform(dim, res);
        s.factors.push(FactorSpec {
            input: Input::Uv,
            param: Param::Uv,
            domain: Domain::Hemisphere,
            res: uv_res,
            smooth: defaults::SMOOTH_UV,
            damp: 0.0,
            ridge: defaults::RIDGE_UV,
            warp: 1.0,
            lean: 1.0,
        });
        s
    }

    /// The default $p(l)\,q(h)\,r(v)$ times a factor of $\theta_d$, $s(\theta_d)$ with `res`
    /// nodes ([`FactorSpec::difference`]): half/difference coordinates (Rusinkiewicz 1998)
    /// for Fresnel and grazing terms.
    pub fn with_difference(res: usize) -> Settings {
        let mut s = Settings::default();
        s.factors.push(FactorSpec::difference(res));
        s
    }

    /// `self` with its light factors drawn to their physical shape where the samples leave
    /// them free: [`Settings::light_prior`] with floor `floor`, and first-difference damping
    /// `damp` of their deviation from it.
    pub fn with_light_prior(&self, damp: f64, floor: f64) -> Settings {
        let mut s = self.clone();
        for f in s.factors.iter_mut().filter(|f| f.input == Input::Light) {
            f.damp = damp;
        }
        s.light_prior = Some(floor);
        s
    }

    /// The settings to fit the samples of `pattern` with: `self`, and where the samples are
    /// headlit ([`super::headlit`]) and `self` has no light prior, the light prior
    /// ([`defaults::DAMP_HEADLIT`], [`defaults::LIGHT_FLOOR`]).
    ///
    /// Why: with the light at the eye, $\theta_l$, $\theta_h$ and $\theta_v$ move together and
    /// the samples fix only the product along that diagonal; a slope in log space moved from
    /// $q$ to $p$ leaves them unchanged, and the Laplacian does not see a slope. Left free,
    /// a headlit Lambertian sphere with stray black strokes had $p$ rising ×3·10⁴ toward
    /// grazing light and $q$ falling as much; the bound then cut one and not the other, and
    /// the fit's error on its own samples was 0.9986 (0.0002 clean). The prior puts the
    /// falloff in the light factor, as irradiance has it, so the material darkens when the
    /// light moves behind; a lobe at the eye stays in $q$. Lit spheres get the same prior,
    /// stronger ([`crate::litsphere::settings`]).
    pub fn for_pattern(&self, pattern: &super::Pattern) -> Settings {
        match self.light_prior.is_none() && pattern.headlit() {
            true => self.with_light_prior(defaults::DAMP_HEADLIT, defaults::LIGHT_FLOOR),
            false => self.clone(),
        }
    }

    /// `self` with a factor of $\theta_d$ ([`FactorSpec::difference`], smoothed like the
    /// light factor, so one $\lambda$ still sets every 1D table) unless it has one already.
    pub fn and_difference(&self) -> Settings {
        let mut s = self.clone();
        if !s.factors.iter().any(|f| matches!(f.input, Input::Difference | Input::HalfDifference)) {
            let mut f = FactorSpec::difference(defaults::RES_DIFFERENCE);
            f.smooth = s.factors.first().filter(|f| f.dim() == 1).map_or(f.smooth, |l| l.smooth);
            s.factors.push(f);
        }
        s
    }

    /// $p(l)\,q(\theta_h, \theta_d)\,r(v)$: the half-vector factor replaced by a 2D table
    /// of $(\theta_h, \theta_d)$, `res_h` × `res_h` nodes. Its smoothing is the 2D default;
    /// the weak damping of 2D tables keeps the $\theta_d$ rows no painting reaches near
    /// constant.
    pub fn half_difference(res_h: usize) -> Settings {
        let mut s = Settings::default();
        s.factors[1] = FactorSpec {
            input: Input::HalfDifference,
            param: Param::Radii,
            domain: Domain::Sphere,
            res: res_h,
            smooth: defaults::SMOOTH_2D,
            damp: defaults::DAMP_2D_FREE,
            ridge: 0.0,
            warp: 1.0,
            lean: 1.0,
        };
        s
    }

    /// The default with the half-vector factor's nodes warped by `warp` (see
    /// [`FactorSpec::warp`]); 1 is the thesis's unwarped table.
    pub fn warped(warp: f64) -> Settings {
        let mut s = Settings::default();
        s.factors[1].warp = warp;
        s
    }

    /// Total unknowns per channel.
    pub fn unknowns(&self) -> usize {
        self.factors.iter().map(FactorSpec::len).sum()
    }

    /// Check resolutions and weights; absurd values are an error naming the factor.
    pub fn validate(&self) -> Result<()> {
        if self.factors.is_empty() {
            return Err(Error::input("no factors: at least one is needed"));
        }
        for (j, f) in self.factors.iter().enumerate() {
            let max = if f.dim() == 1 { MAX_RES_1D } else { MAX_RES_2D };
            if f.res < 2 || f.res > max {
                return Err(Error::input(format!(
                    "factor {j} ({}): resolution {} is outside 2..={max}",
                    f.input.name(),
                    f.res
                )));
            }
            for (what, x) in [("smooth", f.smooth), ("damp", f.damp), ("ridge", f.ridge)] {
                if !x.is_finite() || x < 0.0 {
                    return Err(Error::input(format!(
                        "factor {j} ({}): {what} weight {x} must be a finite non-negative number",
                        f.input.name()
                    )));
                }
            }
            let radial = matches!(f.param, Param::Radius | Param::Radii);
            if !f.warp.is_finite() || f.warp < 1.0 || f.warp > MAX_WARP || (f.warp != 1.0 && !radial) {
                return Err(Error::input(format!(
                    "factor {j} ({}): node warp {} must be in 1..={MAX_WARP}, and 1 unless the table is a radius",
                    f.input.name(),
                    f.warp
                )));
            }
            if !LEAN_RANGE.contains(&f.lean) || (f.lean != 1.0 && f.input != Input::Half) {
                return Err(Error::input(format!(
                    "factor {j} ({}): lean {} must be in {}..={}, and 1 unless the factor looks up the half vector",
                    f.input.name(),
                    f.lean,
                    LEAN_RANGE.start(),
                    LEAN_RANGE.end()
                )));
            }
            // uv goes with uv, the (h, d) pair with two radii, and those only with each other.
            let paired = |input: &Input, param: Param| match input {
                Input::Uv => param == Param::Uv,
                Input::HalfDifference => param == Param::Radii,
                Input::Custom(_) => true,
                _ => param != Param::Uv && param != Param::Radii,
            };
            if !paired(&f.input, f.param) {
                return Err(Error::input(format!(
                    "factor {j}: input '{}' cannot use the {:?} parameterization",
                    f.input.name(),
                    f.param
                )));
            }
        }
        if let Some(e) = self.light_prior.filter(|e| !(e.is_finite() && *e > 0.0 && *e <= 1.0)) {
            return Err(Error::input(format!("light prior floor {e} must be in (0, 1]")));
        }
        if !(0.0..=90.0).contains(&self.light_radius_deg) {
            return Err(Error::input(format!("key light radius {} degrees must be in [0, 90]", self.light_radius_deg)));
        }
        if self.unknowns() > MAX_UNKNOWNS {
            return Err(Error::input(format!(
                "{} unknowns is more than the {MAX_UNKNOWNS} this solver accepts",
                self.unknowns()
            )));
        }
        match self.method {
            Method::TruncatedSvd { rel_tol: x } | Method::DampedSvd { alpha: x } | Method::LinearSvd { gamma: x }
                if !x.is_finite() || x < 0.0 =>
            {
                Err(Error::input(format!("solve method parameter {x} must be finite and non-negative")))
            }
            _ => Ok(()),
        }
    }

    /// A stable fingerprint of the settings, for cache keys.
    pub fn fingerprint(&self) -> u64 {
        let mut h = crate::util::Fnv::new();
        h.write(serde_json::to_string(self).unwrap_or_default().as_bytes());
        h.finish()
    }
}

/// Whether a uniform fit adds a factor of $\theta_d$ (issue 15; `fit --theta-d`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DifferenceChoice {
    /// When the paintings show $\theta_d$ over a range of at least [`DIFFERENCE_SPREAD_DEG`]
    /// reaching [`DIFFERENCE_REACH_DEG`] ([`DifferenceChoice::wants`]).
    #[default]
    Auto,
    /// Always.
    On,
    /// Never: the thesis's $p(l)\,q(h)\,r(v)$.
    Off,
}

/// The range of $\theta_d$ (degrees, [`difference_range`]) from which `auto` adds a factor
/// of $\theta_d$. A painting under a distant light seen by a distant camera shows one
/// $\theta_d$, half the light-camera angle; the three standard paintings of the wide suite show
/// 18°, 22° and 28° (a range of 11°), where $s(\theta_d)$ has nothing to learn and costs a
/// little (median 0.0316 → 0.0326); the three wide ones (key, side and back light) show 17°
/// to 76°, where it helps (0.0433 → 0.0421 with the base, 0.069 → 0.053 without;
/// BENCHMARKS.md, "Automatic θ_d").
pub const DIFFERENCE_SPREAD_DEG: f64 = 20.0;

/// How far the range must reach (its 95th percentile, degrees). The factor is for Fresnel
/// and grazing terms, which start late: Schlick's $(1 - \cos\theta_d)^5$ is 4e-5 at 30° and
/// 0.006 at 50°. The demo's two gold-paint paintings show 17° to 41° and fitted with the
/// factor generalize worse (held-out 0.0371 → 0.0396); the wide suite reaches 76°.
pub const DIFFERENCE_REACH_DEG: f64 = 45.0;

/// The 5th and 95th percentiles of $\theta_d = \angle(l, h)$ over `pattern`'s queries, in
/// degrees (zeros for an empty pattern).
pub fn difference_range(pattern: &super::Pattern) -> [f64; 2] {
    let mut d: Vec<f64> = pattern.queries.iter().map(|q| q.l.dot(q.h()).clamp(-1.0, 1.0).acos().to_degrees()).collect();
    if d.is_empty() {
        return [0.0; 2];
    }
    d.sort_by(f64::total_cmp);
    let at = |p: f64| d[((d.len() - 1) as f64 * p).round() as usize];
    [at(0.05), at(0.95)]
}

impl DifferenceChoice {
    /// Whether the choice adds a factor of $\theta_d$ to a fit of `pattern`.
    pub fn wants(self, pattern: &super::Pattern) -> bool {
        match self {
            DifferenceChoice::On => true,
            DifferenceChoice::Off => false,
            DifferenceChoice::Auto => {
                let [lo, hi] = difference_range(pattern);
                hi - lo >= DIFFERENCE_SPREAD_DEG && hi >= DIFFERENCE_REACH_DEG
            }
        }
    }

    /// The settings to fit `pattern` with, and whether a factor of $\theta_d$ was added.
    pub fn apply(self, settings: &Settings, pattern: &super::Pattern) -> (Settings, bool) {
        let with = settings.and_difference();
        match self.wants(pattern) && with.factors.len() > settings.factors.len() {
            true => (with, true),
            false => (settings.clone(), false),
        }
    }
}

impl fmt::Display for DifferenceChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DifferenceChoice::Auto => "auto",
            DifferenceChoice::On => "on",
            DifferenceChoice::Off => "off",
        })
    }
}

impl std::str::FromStr for DifferenceChoice {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "auto" => Ok(DifferenceChoice::Auto),
            "on" => Ok(DifferenceChoice::On),
            "off" => Ok(DifferenceChoice::Off),
            _ => Err(Error::input(format!("unknown θ_d factor choice '{s}': expected auto, on or off"))),
        }
    }
}

/// How the colour channels are fitted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Channels {
    /// Luminance with the settings as given, chroma one table at a time and drawn to the
    /// painting's mean colour where no sample says otherwise ([`super::chroma`]).
    Coupled,
    /// Each channel on its own, as in the thesis: the default, which a lit sphere leaves for
    /// coupled channels when it takes colours the picture does not have
    /// (`litsphere::colours`).
    #[default]
    Independent,
}

impl Channels {
    /// The thesis's choice: what settings without a `channels` field were fitted with.
    pub fn thesis() -> Channels {
        Channels::Independent
    }
}

impl fmt::Display for Channels {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Channels::Coupled => "coupled",
            Channels::Independent => "independent",
        })
    }
}

impl FromStr for Channels {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "coupled" => Ok(Channels::Coupled),
            "independent" => Ok(Channels::Independent),
            _ => Err(Error::input(format!("unknown channel fit '{s}': expected coupled or independent"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factor::{Pattern, Query};
    use glam::DVec3;

    /// A light `deg` from the camera, turned about y.
    fn light(deg: f64) -> DVec3 {
        let r = deg.to_radians();
        DVec3::new(r.sin(), 0.0, r.cos())
    }

    /// θ_d is half the light-camera angle: lights 20° and 100° from the camera give 10° and
    /// 50°, a range of 40° reaching past 45°, and `auto` adds the factor (smoothed like the
    /// light factor); one light gives one θ_d, and 20° and 80° (10° to 40°) do not reach
    /// Fresnel's angles: no factor.
    #[test]
    fn auto_adds_a_difference_factor_when_the_range_is_wide() {
        let queries = |lights: &[f64]| Pattern::new(lights.iter().flat_map(|&d| (0..50).map(move |_| Query::at(light(d), DVec3::Z))).collect(), false);
        let wide = queries(&[20.0, 100.0]);
        let [lo, hi] = difference_range(&wide);
        assert!((lo - 10.0).abs() < 1e-9 && (hi - 50.0).abs() < 1e-9, "{lo} {hi}");
        let mut settings = Settings::default();
        settings.factors[0].smooth = 3e-5;
        let (with, added) = DifferenceChoice::Auto.apply(&settings, &wide);
        assert!(added);
        assert_eq!(with.factors.len(), 4);
        assert_eq!(with.factors[3].input, Input::Difference);
        assert_eq!(with.factors[3].smooth, 3e-5);
        let narrow = queries(&[20.0]);
        assert!(difference_range(&narrow).iter().all(|d| (d - 10.0).abs() < 1e-9));
        assert!(!DifferenceChoice::Auto.apply(&settings, &narrow).1);
        assert!(!DifferenceChoice::Auto.apply(&settings, &queries(&[20.0, 80.0])).1);
        assert!(!DifferenceChoice::Off.apply(&settings, &wide).1);
        assert!(DifferenceChoice::On.apply(&settings, &narrow).1);
        // A product that has a factor of θ_d already gets no second one.
        assert!(!DifferenceChoice::On.apply(&with, &wide).1);
    }
}
