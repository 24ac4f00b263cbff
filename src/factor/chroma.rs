//! Colour channels fitted together (issue 35).
//!
//! The thesis solves each channel's factors on its own (eq. 3.4 with three right-hand
//! sides). Where the samples say little (the near-null direction of one view, directions no
//! sample reaches) the three channels extrapolate differently, and their ratio, the hue,
//! swings: a grey MatCap can turn orange-and-cyan under a side light. A painter never
//! paints that. [`Channels::Coupled`] splits every log value into a luminance and a chroma,
//!
//! $\tilde f_c = \tilde L + \tilde\rho_c, \qquad \tilde L = \sum_c \alpha_c \tilde f_c,$
//!
//! with $\alpha_c = w_c g_c / \sum_k w_k g_k$ (Rec. 709 weights $w$, the painting's geometric
//! mean colour $g$): $\tilde L$ is $\log Y$ linearised at the painting's mean colour, so a
//! red painting's shading is carried by its red channel and a grey one's by all three. The
//! split is linear, so both parts are solves of prepared systems (thesis 3.2.2 holds):
//! - the luminance on the system of the settings as given, today's fit;
//! - the chroma on a second system ([`Settings::chroma`]), smoother, damped, and with a ridge
//!   toward the painting's mean chroma: where the painting does not say what colour a
//!   direction has, it has the painting's colour; where it does (a Gooch painting's cool
//!   side, a painted rim), the samples outweigh the prior.
//!
//! The tables stay RGB: each is $e^{\tilde L_j + \tilde\rho_{j,c}}$, the product of the two.
//! The offset and inverted mappings apply their constant after the product (eqs. 3.14,
//! 3.16), so under coupled channels the constants are one colour, the painting's mean
//! ([`Mapping::candidates_tinted`](super::Mapping::candidates_tinted)): where the chroma is
//! the mean, $\prod - a$ and $a - \prod$ keep it.

use std::fmt;
use std::str::FromStr;

use faer::Mat;
use serde::{Deserialize, Serialize};

use super::prepared::Prepared;
use super::settings::{Input, Settings};
use crate::error::{Error, Result};

/// How the colour channels are fitted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Channels {
    /// Luminance with the settings as given, chroma smoother and drawn to the painting's
    /// mean colour (this module). Opt-in: its damping and ridge also act where the samples
    /// show a hue change (a white highlight on a coloured body), see BENCHMARKS.md.
    Coupled,
    /// Each channel on its own, as in the thesis: the default.
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

/// Rec. 709 luminance weights of linear sRGB primaries (the colour space paintings decode to).
pub const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The chroma's Laplacian weight over the luminance's, per directional factor. The smoothing
/// term grows with $\lambda^2$: 10 makes a hue change a hundred times dearer than the same
/// change of brightness, so colour moves over the whole table, not between nodes.
pub const CHROMA_SMOOTH_GAIN: f64 = 10.0;

/// First-difference damping $\mu$ of every directional factor's chroma. The term is $\mu N
/// \int |\nabla\tilde\rho|^2$ against the samples' $\sum_i r_i^2$ over the same $N$ samples:
/// a hue ramp the samples show costs a hundredth of leaving it out, so painted colour wins;
/// a ramp they do not show (the near-null direction of one view) costs only this, and goes.
pub const CHROMA_DAMP: f64 = 1e-2;

/// Ridge $\rho$ of every factor's chroma toward its share of the painting's mean chroma: by
/// the same count as [`CHROMA_DAMP`], a node reached by more than a hundredth of an even
/// share of the samples takes their colour, one reached by none the painting's.
pub const CHROMA_RIDGE: f64 = 1e-2;

impl Settings {
    /// These settings for the luminance: the factors as given, channels solved alike.
    pub fn luminance(&self) -> Settings {
        Settings { channels: Channels::Independent, ..self.clone() }
    }

    /// The system of the chroma ([`CHROMA_SMOOTH_GAIN`], [`CHROMA_DAMP`], [`CHROMA_RIDGE`]).
    /// The uv factor keeps its smoothing and damping: a texture's colour edges are painted
    /// detail, not extrapolation. No light prior: it shapes brightness, not colour.
    pub fn chroma(&self) -> Settings {
        let mut s = self.luminance();
        s.light_prior = None;
        for f in &mut s.factors {
            if f.input != Input::Uv {
                f.smooth *= CHROMA_SMOOTH_GAIN;
                f.damp = f.damp.max(CHROMA_DAMP);
            }
            f.ridge = f.ridge.max(CHROMA_RIDGE);
        }
        s
    }
}

/// The chroma half of a coupled system: its prepared system and the ridge's weight per node
/// (the ridge pulls toward a target, which moves only the right-hand side).
pub(crate) struct Coupled {
    pub(crate) chroma: Box<Prepared>,
    /// $\rho N h^d$ per node over the factor count: each factor takes an equal share of the
    /// mean chroma, so their sum, the product's chroma, is the mean.
    target: Vec<f64>,
}

impl Coupled {
    pub(crate) fn new(chroma: Prepared) -> Coupled {
        let (settings, design, _) = chroma.parts();
        let n_samples = design.rows() as f64;
        let count = settings.factors.len() as f64;
        let target = settings
            .factors
            .iter()
            .flat_map(|f| {
                let cell = (1.0 / (f.res - 1) as f64).powi(f.dim() as i32);
                std::iter::repeat_n(f.ridge * n_samples * cell / count, f.len())
            })
            .collect();
        Coupled { chroma: Box::new(chroma), target }
    }

    /// Log-space tables for the right-hand side $\mathbf b = \mathbf A^\top\tilde{\mathbf f}$
    /// (plus any prior), `luminance` solving on the first system.
    pub(crate) fn apply(&self, luminance: &Prepared, b: &Mat<f64>) -> Mat<f64> {
        let (_, design, _) = luminance.parts();
        let n = design.n;
        // Every sample's stencil in the first factor sums to 1, so that factor's rows of b
        // sum to the samples' log values (priors add rows that sum to zero).
        let first = design.offsets.get(1).copied().unwrap_or(n);
        let rows = design.rows().max(1) as f64;
        let mean: [f64; 3] = [0, 1, 2].map(|c| (0..first).map(|i| b[(i, c)]).sum::<f64>() / rows);
        let alpha = weights(mean);
        let lum_mean: f64 = (0..3).map(|c| alpha[c] * mean[c]).sum();
        let y = luminance.solve_system(b);
        let mut rhs = Mat::from_fn(n, 3, |i, c| b[(i, c)] - (0..3).map(|k| alpha[k] * b[(i, k)]).sum::<f64>());
        for (i, t) in self.target.iter().enumerate() {
            for c in 0..3 {
                rhs[(i, c)] += t * (mean[c] - lum_mean);
            }
        }
        let rho = self.chroma.solve_system(&rhs);
        Mat::from_fn(n, 3, |i, c| (0..3).map(|k| alpha[k] * y[(i, k)]).sum::<f64>() + rho[(i, c)])
    }
}

/// $\alpha_c = w_c g_c / \sum_k w_k g_k$ for mean log values `mean` ($g = e^{\text{mean}}$).
fn weights(mean: [f64; 3]) -> [f64; 3] {
    let top = mean.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let g = [0, 1, 2].map(|c| LUMA[c] * (mean[c] - top).exp());
    let sum: f64 = g.iter().sum();
    if !(sum.is_finite() && sum > 0.0) {
        return LUMA;
    }
    g.map(|x| x / sum)
}

/// The painting's mean colour, scaled so its largest channel is 1 and none is below
/// `floor` (a channel the painting never shows still gets a finite log).
pub(crate) fn tint(values: &[[f64; 3]], floor: f64) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for v in values {
        for c in 0..3 {
            sum[c] += v[c];
        }
    }
    let top = sum.iter().cloned().fold(0.0, f64::max);
    if !(top.is_finite() && top > 0.0) {
        return [1.0; 3];
    }
    sum.map(|s| (s / top).max(floor))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_prints_both_choices() {
        for c in [Channels::Coupled, Channels::Independent] {
            assert_eq!(c.to_string().parse::<Channels>().unwrap(), c);
        }
        let e = "rgb".parse::<Channels>().unwrap_err().to_string();
        assert!(e.contains("coupled or independent") && !e.contains('\n'), "{e}");
    }

    #[test]
    fn luminance_weights_follow_the_mean_colour() {
        // Grey: Rec. 709 itself.
        let w = weights([0.0; 3]);
        assert!((0..3).all(|c| (w[c] - LUMA[c]).abs() < 1e-12), "{w:?}");
        // Red with green and blue 1000 times darker: red carries the luminance.
        let w = weights([0.0, -(1000f64).ln(), -(1000f64).ln()]);
        assert!(w[0] > 0.99 && (w.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{w:?}");
    }

    #[test]
    fn chroma_settings_are_smoother_damped_and_ridged() {
        let s = Settings::four_factor(1, 16, 8);
        let c = s.chroma();
        assert_eq!(c.channels, Channels::Independent);
        for (a, b) in s.factors.iter().zip(&c.factors) {
            assert!(b.ridge >= CHROMA_RIDGE);
            if a.input != Input::Uv {
                assert_eq!(b.smooth, a.smooth * CHROMA_SMOOTH_GAIN);
                assert!(b.damp >= CHROMA_DAMP);
            } else {
                assert_eq!((b.smooth, b.damp), (a.smooth, a.damp));
            }
        }
    }
}
