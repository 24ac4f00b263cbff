//! Stylized pictures: toon and cel-shaded spheres read as drawn (issue 36, the thesis's
//! "non-photorealistic effects").
//!
//! A physical reading smooths: the light prior draws the light factor towards $\cos\theta_l$,
//! the Laplacian rounds every step, and a light estimated under Lambert's model sits where a
//! smooth shading would put it, not where the painter's tone edges say. A stylized reading
//! keeps what the painter drew:
//!
//! - **The light from the tone edges** ([`super::light::estimate_tone_light`]): the direction
//!   under which the picture is a function of $n \cdot l$ alone, whatever that function is
//!   (two tones, three, a gradient), so every terminator follows the light.
//! - **Tables as fine as the picture** ([`resolution`]) and a weak Laplacian
//!   ([`STYLIZED_SMOOTH`]): a step between two tones stays a step of a pixel or two.
//! - **No light prior**: the painting says how the light factor falls, everywhere it shows.
//! - **A robust solve** (Huber, then Tukey's biweight: [`robust`]): a tone edge painted a
//!   pixel off the light's circle is an outlier to the step, not a reason to blur it.
//!
//! The settings are decided once per picture, before prepare, which stays free of pixel
//! values (DESIGN.md). `--style auto` decides by [`Tones::stylized`].

use super::Disk;
use crate::factor::{Input, Robust, Settings};
use crate::images::{linear_to_srgb, luminance, Painting};

/// How a lit-sphere picture is read (`fit --style`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A sphere shaded as light does: smooth, with the physical light prior.
    Physical,
    /// A drawing whose tones, edges and highlight shape are kept as drawn.
    Stylized,
    /// Stylized when the picture is a few flat tones with hard edges ([`Tones::stylized`]).
    Auto,
}

/// What the disk's luminance histogram shows: its flat tones and how much of the disk they
/// hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tones {
    /// Flat tones found: histogram peaks of at least [`MIN_TONE`] of the disk.
    pub count: usize,
    /// Share of the disk's pixels within [`TONE_WIDTH`] codes of one of them.
    pub share: f64,
    /// Share of the disk's luminance range (1st to 99th percentile) the tones' windows cover.
    pub span: f64,
}

/// Half-width of a flat tone, in 8-bit sRGB codes: a flat tone seen through JPEG and paper
/// grain scatters by about 1.5 codes (σ), so ±4 keeps 99% of its pixels.
pub const TONE_WIDTH: usize = 4;

/// Smallest share of the disk a tone holds: a highlight of a tenth of the radius across is
/// 1% of the disk.
pub const MIN_TONE: f64 = 0.01;

/// Most tones of a stylized picture: cel shading uses two to four, a posterized one more.
pub const MAX_TONES: usize = 8;

/// A stylized picture's tones hold at least this share of its disk (the rest: the
/// anti-aliased edges between them, a pixel or two wide, and strokes).
pub const STYLIZED_SHARE: f64 = 0.9;

/// ... while their windows cover at most this share of its luminance range. A smooth
/// shading spreads its pixels over its range, so its mass in a set of windows is about the
/// share of the range they cover: 90% of it in half the range is a picture of flat tones.
pub const STYLIZED_SPAN: f64 = 0.5;

impl Tones {
    /// A few flat tones with hard edges: [`STYLIZED_SHARE`] of the disk in at most
    /// [`MAX_TONES`] tones (two or more) whose windows cover at most [`STYLIZED_SPAN`] of its
    /// luminance range.
    pub fn stylized(&self) -> bool {
        (2..=MAX_TONES).contains(&self.count) && self.share >= STYLIZED_SHARE && self.span <= STYLIZED_SPAN
    }
}

/// The tones of the disk of `p` (inside 95% of its radius, off the rim): peaks of the
/// histogram of sRGB luminance codes, taken greedily, highest first, each claiming the codes
/// within [`TONE_WIDTH`] of it.
pub fn tones(p: &Painting, disk: &Disk) -> Tones {
    let mut histogram = [0usize; 256];
    for j in 0..p.height {
        for i in 0..p.width {
            let k = j * p.width + i;
            if p.alpha[k] > 0.0 && disk.normal(i, j, 0.95).is_some() {
                let y = linear_to_srgb(luminance(p.pixels[k].map(f64::from)) as f32);
                histogram[code(y)] += 1;
            }
        }
    }
    tones_of(&histogram)
}

/// The sRGB code (0 to 255) of a value in [0, 1].
fn code(y: f32) -> usize {
    (y * 255.0).round().clamp(0.0, 255.0) as usize
}

/// A painted picture's shading profile along the light ([`profile`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// The tones of the profile, each band counted for its pixels ([`tones`] of them).
    pub tones: Tones,
    /// How much lighter the quarter of the disk nearest the light is than the farthest, over
    /// the profile's range (-1 to 1).
    pub rise: f64,
}

/// A drawing lit by one light is lighter towards it: a toon sphere's lit tone against its
/// shadow tone is its whole range; reflections of an environment (a MatCap's stripes, a
/// metal's horizon) are as light on either side.
pub const MIN_RISE: f64 = 0.5;

impl Profile {
    /// A painted drawing: its profile is a few flat tones ([`Tones::stylized`]) lighter
    /// towards the light ([`MIN_RISE`]).
    pub fn drawn(&self) -> bool {
        self.tones.stylized() && self.rise >= MIN_RISE
    }
}

/// Pixel-level texture below which a picture is clean, in sRGB codes: 8-bit quantization
/// alone leaves a residual of 0.32 codes against the mean of the four neighbours (uniform
/// within ±½ code: 0.29, times √(1 + 4/16)); a clean render or a digital drawing has about
/// that, paint's strokes and paper grain more.
pub const CLEAN_GRAIN: f64 = 0.5;

/// The disk's pixel-level texture (inside 90% of its radius): the robust standard deviation
/// of each pixel's sRGB luminance code less the mean of its four neighbours.
pub fn grain(p: &Painting, disk: &Disk) -> f64 {
    let y: Vec<f64> = p.pixels.iter().map(|c| 255.0 * f64::from(linear_to_srgb(luminance(c.map(f64::from)) as f32))).collect();
    let w = p.width;
    let mut residual: Vec<f64> = Vec::new();
    for j in 1..p.height.saturating_sub(1) {
        for i in 1..w - 1 {
            let k = j * w + i;
            if p.alpha[k] > 0.0 && disk.normal(i, j, 0.9).is_some() {
                residual.push((y[k] - 0.25 * (y[k - 1] + y[k + 1] + y[k - w] + y[k + w])).abs());
            }
        }
    }
    if residual.is_empty() {
        return 0.0;
    }
    residual.sort_by(f64::total_cmp);
    1.4826 * residual[residual.len() / 2]
}

/// The shading profile of the disk under the light `l`: the median luminance of each band of
/// $n \cdot l$ ([`super::light::shading_profile`]). A painted flat tone scatters by its
/// strokes and grain far beyond [`TONE_WIDTH`], but a band's median, taken around the whole
/// ring, does not; a smooth shading's profile spreads over its range as its pixels do.
pub fn profile(p: &Painting, disk: &Disk, l: glam::DVec3) -> Profile {
    let bands = super::light::shading_profile(p, disk, l);
    let mut histogram = [0usize; 256];
    for &(y, n) in &bands {
        histogram[code(y as f32)] += n;
    }
    let (lo, hi) = bands.iter().fold((f64::MAX, f64::MIN), |(lo, hi), b| (lo.min(b.0), hi.max(b.0)));
    let total: usize = bands.iter().map(|b| b.1).sum();
    let rise = if hi > lo { (quarter_median(bands.iter().rev(), total) - quarter_median(bands.iter(), total)) / (hi - lo) } else { 0.0 };
    Profile { tones: tones_of(&histogram), rise }
}

/// The median value of the first `bands` (value, pixels) that hold a quarter of `total` pixels.
fn quarter_median<'a>(bands: impl Iterator<Item = &'a (f64, usize)>, total: usize) -> f64 {
    let mut held = 0;
    let mut ys: Vec<f64> = bands
        .take_while(|b| {
            let before = held;
            held += b.1;
            4 * before < total
        })
        .map(|b| b.0)
        .collect();
    ys.sort_by(f64::total_cmp);
    ys.get(ys.len() / 2).copied().unwrap_or(0.0)
}

/// The flat tones of a histogram of sRGB codes: its peaks, taken greedily, highest first,
/// each claiming the codes within [`TONE_WIDTH`] of it.
fn tones_of(histogram: &[usize; 256]) -> Tones {
    let total: usize = histogram.iter().sum();
    if total == 0 {
        return Tones { count: 0, share: 0.0, span: 1.0 };
    }
    let percentile = |q: f64| {
        let target = (q * total as f64) as usize;
        let mut seen = 0;
        histogram.iter().position(|&n| {
            seen += n;
            seen > target
        })
    };
    let range = percentile(0.99).unwrap_or(255).saturating_sub(percentile(0.01).unwrap_or(0)) + 1;
    let mut left = *histogram;
    let (mut count, mut held, mut covered) = (0usize, 0usize, 0usize);
    while count <= MAX_TONES {
        let Some((peak, _)) = left.iter().enumerate().max_by_key(|&(_, &n)| n) else { break };
        let window = peak.saturating_sub(TONE_WIDTH)..=(peak + TONE_WIDTH).min(255);
        let mass: usize = left[window.clone()].iter().sum();
        if (mass as f64) < MIN_TONE * total as f64 {
            break;
        }
        covered += left[window.clone()].iter().filter(|&&n| n > 0).count();
        held += mass;
        count += 1;
        left[window].iter_mut().for_each(|n| *n = 0);
    }
    Tones { count, share: held as f64 / total as f64, span: (covered as f64 / range as f64).min(1.0) }
}

/// The Laplacian weight of a stylized fit's tables: weak, so a step between tones stays a
/// step. The tables' shape where no pixel reaches them does not depend on it (the
/// Laplacian's null space, a straight line, fills them at any weight).
pub const STYLIZED_SMOOTH: f64 = 1e-7;

/// Nodes of a stylized fit's 1D tables: about one per pixel of the disk's radius. The
/// radius map $t = \tan(\theta/2)/2$ has $d\theta/dt \le 4$, so $M$ nodes are at most
/// $4/M$ radians apart, and a pixel at the disk's centre spans $1/r$: $M = 2r$ puts a tone
/// edge within two pixels. Clamped to the default and 1024.
pub fn resolution(disk: &Disk) -> usize {
    ((2.0 * disk.r).round() as usize).clamp(crate::factor::defaults::RES_1D, 1024)
}

/// The settings of a stylized fit from the user's (`base`): every 1D table of a direction
/// at [`resolution`] nodes unless `res_given`, smoothed by [`STYLIZED_SMOOTH`] unless
/// `smooth_given`, the half-vector table looking up the highlight's `lean`
/// ([`super::highlight_lean`]), and no light prior.
pub fn settings(base: &Settings, disk: &Disk, lean: f64, res_given: bool, smooth_given: bool) -> Settings {
    let mut s = base.clone();
    for f in s.factors.iter_mut().filter(|f| f.dim() == 1 && matches!(f.input, Input::Light | Input::Half | Input::View)) {
        if !res_given {
            f.res = resolution(disk);
        }
        if !smooth_given {
            f.smooth = STYLIZED_SMOOTH;
        }
        if f.input == Input::Half {
            f.lean = lean;
        }
    }
    s.light_prior = None;
    s
}

/// The robust solve of a stylized fit: Huber's ψ to start (convex), then Tukey's biweight,
/// which gives a tone edge painted off the light's circle no weight; no paint levels (the
/// tones are the drawing, not a quantizer's steps to smooth over); a looser bound
/// ([`STYLIZED_BOUND`]); and, with no light prior to shape them, tables that hold their
/// last drawn tone where the picture shows nothing (a light further behind, a half vector
/// further out).
pub fn robust() -> Robust {
    Robust { huber: 4, tukey: 6, max_levels: 0, light_prior: None, bound: STYLIZED_BOUND, hold_unseen: true, ..Robust::default() }
}

/// The bound of a stylized fit's product over light and view directions the picture does
/// not show ([`crate::factor::bound::bound_log`]), × its largest value. A drawing's tones
/// are far apart (a black outline is 1/500 of its body in linear light) and, free of the
/// light prior, the product extrapolates past the physical fit's 8× where one view says
/// nothing; cut to 8×, the whole material was scaled down to fit under it (a toon sphere
/// with an outline: RMS 0.075 against 0.027). 64 still stops a stray stroke's $10^{10}$.
pub const STYLIZED_BOUND: f64 = 64.0;

#[cfg(test)]
mod tests {
    use super::*;

    /// A disk of radius 40 whose pixels take `value(x)` (sRGB code / 255, x in [-1, 1]).
    fn disk_of(value: impl Fn(f64) -> f64) -> (Painting, Disk) {
        let (w, disk) = (100, Disk { cx: 50.0, cy: 50.0, r: 40.0 });
        let pixels = (0..w * w)
            .map(|k| {
                let x = ((k % w) as f64 + 0.5 - disk.cx) / disk.r;
                [crate::images::srgb_to_linear(value(x).clamp(-1.0, 1.0) as f32); 3]
            })
            .collect();
        (Painting::opaque(w, w, pixels).unwrap(), disk)
    }

    #[test]
    fn two_flat_tones_are_stylized_and_a_ramp_is_not() {
        let (p, d) = disk_of(|x| if x < 0.2 { 0.3 } else { 0.8 });
        let t = tones(&p, &d);
        assert_eq!(t.count, 2, "{t:?}");
        assert!(t.share > 0.99 && t.stylized(), "{t:?}");
        // A ramp over 40% of the codes: its pixels spread evenly, so no few windows hold 90%.
        let (p, d) = disk_of(|x| 0.5 + 0.2 * x);
        let t = tones(&p, &d);
        assert!(!t.stylized() && t.share < STYLIZED_SHARE, "{t:?}");
    }
}
