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
//! - the chroma table by table ([`Settings::chroma`]: one system per factor, that factor
//!   alone): stage by stage, the table that explains most of what is left of the samples'
//!   chroma takes it. One table's least-squares fit is a weighted mean of the samples' chroma
//!   at each node, so two tables cannot hold large opposite hues that one view only showed
//!   together, and a ridge keeps the painting's mean chroma on nodes no sample reaches:
//!   where the painting says what colour a direction has (a Gooch painting's cool side, a
//!   painted rim), the samples outweigh it.
//!
//! The tables stay RGB: each is $e^{\tilde L_j + \tilde\rho_{j,c}}$, the product of the two.
//! The offset and inverted mappings apply their constant after the product (eqs. 3.14,
//! 3.16), so under coupled channels the constants are one colour, the painting's mean
//! ([`Mapping::candidates_tinted`](super::Mapping::candidates_tinted)): where the chroma is
//! the mean, $\prod - a$ and $a - \prod$ keep it.

use faer::Mat;

use super::settings::{Channels, Input, Settings};
use super::system::Design;

/// A prepared least-squares system the chroma solves on: its settings and sample matrix,
/// and its solve for a right-hand side (eq. 3.4's normal equations, factored once).
pub(crate) trait Solve {
    fn settings(&self) -> &Settings;
    fn design(&self) -> &Design;
    /// Log-space tables for the right-hand side `b` (n × 3).
    fn solve_system(&self, b: &Mat<f64>) -> Mat<f64>;
}

/// Rec. 709 luminance weights of linear sRGB primaries (the colour space paintings decode to).
pub const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Ridge $\rho$ of a factor's chroma toward the painting's mean chroma. The term is $\rho N
/// \int \tilde\rho^2$ against the samples' $\sum_i r_i^2$ over the same $N$ samples: a node
/// reached by more than a hundredth of an even share of the samples takes their colour, one
/// reached by none the painting's.
pub const CHROMA_RIDGE: f64 = 1e-2;

impl Settings {
    /// These settings for the luminance: the factors as given, channels solved alike.
    pub fn luminance(&self) -> Settings {
        Settings { channels: Channels::Independent, ..self.clone() }
    }

    /// The chroma's systems, one per factor, each that factor alone: the product's hue is
    /// then one table's, never the sum of two tables' hues that the samples only showed
    /// together (the near-null direction of one view). Smoothing and damping as the
    /// luminance's (one table alone has no near-null direction to damp), [`CHROMA_RIDGE`] at
    /// least. No light prior: it shapes brightness.
    pub fn chroma(&self) -> Vec<Settings> {
        self.factors
            .iter()
            .map(|f| {
                let mut f = f.clone();
                f.ridge = f.ridge.max(CHROMA_RIDGE);
                Settings { factors: vec![f], light_prior: None, ..self.luminance() }
            })
            .collect()
    }
}

/// One factor's chroma system: the factor's index, its prepared system alone, and the
/// ridge's weight per node ($\rho N h^d$; the ridge pulls toward a target, which moves only
/// the right-hand side).
struct Part {
    factor: usize,
    system: Box<dyn Solve + Send + Sync>,
    ridge: f64,
}

/// The chroma half of a coupled system. The uv factor, where there is one, takes the
/// samples' colour first (a texture's colour is where it was painted); then the directional
/// factors, stage by stage, each the one whose table explains most of what is left.
pub(crate) struct Coupled {
    parts: Vec<Part>,
}

impl Coupled {
    pub(crate) fn new(parts: Vec<Box<dyn Solve + Send + Sync>>) -> Coupled {
        let parts = parts
            .into_iter()
            .enumerate()
            .map(|(factor, system)| {
                let f = &system.settings().factors[0];
                let cell = (1.0 / (f.res - 1) as f64).powi(f.dim() as i32);
                let ridge = f.ridge * system.design().rows() as f64 * cell;
                Part { factor, system, ridge }
            })
            .collect();
        Coupled { parts }
    }

    /// Log-space tables for the right-hand side $\mathbf b = \mathbf A^\top\tilde{\mathbf f}$
    /// (plus any prior), `luminance` solving on the first system.
    pub(crate) fn apply(&self, luminance: &dyn Solve, b: &Mat<f64>) -> Mat<f64> {
        let (settings, design) = (luminance.settings(), luminance.design());
        let n = design.n;
        // Every sample's stencil in the first factor sums to 1, so that factor's rows of b
        // sum to the samples' log values (priors add rows that sum to zero).
        let first = design.offsets.get(1).copied().unwrap_or(n);
        let rows = design.rows().max(1) as f64;
        let mean: [f64; 3] = [0, 1, 2].map(|c| (0..first).map(|i| b[(i, c)]).sum::<f64>() / rows);
        let alpha = weights(mean);
        let lum_mean: f64 = (0..3).map(|c| alpha[c] * mean[c]).sum();
        let y = luminance.solve_system(b);
        let mut out = Mat::from_fn(n, 3, |i, _| (0..3).map(|k| alpha[k] * y[(i, k)]).sum::<f64>());
        let mut rhs = Mat::from_fn(n, 3, |i, c| b[(i, c)] - (0..3).map(|k| alpha[k] * b[(i, k)]).sum::<f64>());
        let mut target = [0, 1, 2].map(|c| mean[c] - lum_mean);
        let range = |j: usize| design.offsets[j]..design.offsets.get(j + 1).copied().unwrap_or(n);
        let uv = settings.factors.iter().position(|f| f.input == Input::Uv);
        if let Some(part) = uv.and_then(|j| self.parts.iter().find(|p| p.factor == j)) {
            let (rho, _) = part.solve(&rhs, range(part.factor), target);
            design.subtract_cross(&mut rhs, range(part.factor), &rho);
            add_rows(&mut out, range(part.factor), &rho);
            target = [0.0; 3];
        }
        // Stage by stage, the directional factor that explains most of what is left takes
        // it: each stage's table is a weighted mean of residual chroma, so a hue that two
        // tables only showed together cannot be split into two large opposite hues.
        let mut left: Vec<&Part> = self.parts.iter().filter(|p| Some(p.factor) != uv).collect();
        while !left.is_empty() {
            let solved: Vec<(Mat<f64>, f64)> = left.iter().map(|p| p.solve(&rhs, range(p.factor), target)).collect();
            let k = (0..solved.len()).max_by(|&a, &b| solved[a].1.total_cmp(&solved[b].1)).unwrap_or(0);
            let part = left.swap_remove(k);
            let rho = &solved[k].0;
            if !left.is_empty() {
                design.subtract_cross(&mut rhs, range(part.factor), rho);
            }
            add_rows(&mut out, range(part.factor), rho);
            target = [0.0; 3];
        }
        out
    }
}

impl Part {
    /// The factor's chroma from its rows of `rhs` and the ridge toward `target`, and how much
    /// of the samples' chroma it explains: $\tilde\rho^\top \mathbf r$, the fall of the
    /// regularized least-squares cost from $\tilde\rho = 0$.
    fn solve(&self, rhs: &Mat<f64>, rows: std::ops::Range<usize>, target: [f64; 3]) -> (Mat<f64>, f64) {
        let r = Mat::from_fn(rows.len(), 3, |i, c| rhs[(rows.start + i, c)] + self.ridge * target[c]);
        let rho = self.system.solve_system(&r);
        let explained = (0..rows.len()).flat_map(|i| (0..3).map(move |c| (i, c))).map(|(i, c)| rho[(i, c)] * r[(i, c)]).sum();
        (rho, explained)
    }
}

/// `out`'s rows `rows` plus `add`.
fn add_rows(out: &mut Mat<f64>, rows: std::ops::Range<usize>, add: &Mat<f64>) {
    for (i, r) in rows.enumerate() {
        for c in 0..3 {
            out[(r, c)] += add[(i, c)];
        }
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
    fn chroma_systems_are_one_factor_each_and_ridged() {
        let s = Settings::four_factor(1, 16, 8);
        let parts = s.chroma();
        assert_eq!(parts.len(), s.factors.len());
        for (a, part) in s.factors.iter().zip(&parts) {
            assert_eq!((part.factors.len(), part.channels, part.light_prior), (1, Channels::Independent, None));
            let b = &part.factors[0];
            assert!(b.ridge >= CHROMA_RIDGE && b.smooth == a.smooth && b.damp == a.damp);
        }
    }
}
