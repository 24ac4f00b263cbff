//! Flat tones (issue 11): a posterized painting read as the smooth shading it suggests.
//!
//! A painting made of a few flat tones per channel (a posterize filter, cel-style value
//! steps, a limited palette) is evidence of a smooth shading seen through a quantizer: a
//! pixel painted at level $L_i$ had a true value in $[m_{i-1}, m_i]$, the midpoints between
//! neighbouring levels, and the true value crosses a midpoint exactly on the edge between two
//! tones. Fitted as it is, the steps go into the 1D tables as rings and cliffs and the
//! material is as posterized as the painting (held-out error 0.18 at 6 levels: BENCHMARKS.md,
//! faults). So each channel is *reconstructed*: inside a tone region the value runs from the
//! lower edge's midpoint to the upper edge's, in proportion to the pixel's Euclidean distance
//! to the nearest darker and brighter tone,
//!
//! $$ x = m_{i-1} + (m_i - m_{i-1}) \frac{d_-}{d_- + d_+}, $$
//!
//! the linear interpolation between the two iso-lines the painting does give. A region with no
//! darker (brighter) neighbour, the shadow core or the highlight's plateau, runs from its one
//! edge's midpoint to half a step beyond its level at its farthest pixel. All in the display
//! (sRGB) code where the quantizer worked.
//!
//! That interpolation is only a guess across a region a third of the sphere wide, so once
//! the light is registered [`refine`] reads the tones again through the physical proxy
//! ([`super::proxy`]) or the lobe family that holds them ([`family`]): the smooth shading that
//! keeps every pixel inside its interval (6 levels: held-out error 0.165 interpolated, 0.068
//! through the proxy, 0.026 through lobe families; BENCHMARKS.md). The few pixels whose tone
//! that reading misses by more than a whole interval are then left out of it, and the tones
//! read again ([`OUTLIER_WIDTHS`]).
//!
//! A painting counts as toned when, over its samples, every channel takes at most
//! [`MAX_LEVELS`] distinct 8-bit codes and some channel at least [`MIN_LEVELS`]: two tones are a
//! toon style to keep, hundreds a painted gradient.

use rayon::prelude::*;

use super::proxy;
use crate::sample::PaintedView;
use crate::brdf::lobe::Lobe;
use crate::images::{self, linear_to_srgb, srgb_to_linear};

/// Most distinct codes per channel of a toned painting.
pub const MAX_LEVELS: usize = 12;
/// Fewest distinct codes (in its busiest channel) of a toned painting; fewer is a toon style.
pub const MIN_LEVELS: usize = 3;
/// Fewest samples worth reconstructing: a small painting's regions are too thin to measure.
const MIN_SAMPLES: usize = 500;

/// What was done to one view's tones.
#[derive(Clone, Debug, PartialEq)]
pub struct Toned {
    /// Distinct codes per channel.
    pub levels: [usize; 3],
    /// Per sample pixel: its index and, per channel, the linear interval its true value
    /// lies in (between the midpoints to the neighbouring levels).
    pub bounds: Vec<(usize, [[f64; 2]; 3])>,
}

impl Toned {
    /// The sample pixels of the brightest tone: whose intervals' lower ends, weighted as
    /// luminance, are the largest.
    pub fn brightest(&self) -> Vec<usize> {
        let floor = |b: &[[f64; 2]; 3]| luminance_interval(b)[0];
        let top = self.bounds.iter().map(|(_, b)| floor(b)).fold(f64::NEG_INFINITY, f64::max);
        self.bounds.iter().filter(|(_, b)| floor(b) >= top).map(|&(k, _)| k).collect()
    }

    /// The note a user reads.
    pub fn note(&self, painting: &str) -> crate::note::Note {
        crate::note::Note::FlatTones { painting: painting.to_string(), levels: self.levels }
    }
}

/// Reconstructs a toned view's painting in place (module doc); `None`, untouched, when the
/// painting is not toned.
pub fn smooth(view: &mut PaintedView) -> Option<Toned> {
    let w = view.painting.width;
    let samples = view.geometry.sample_pixels(&view.painting);
    if samples.len() < MIN_SAMPLES {
        return None;
    }
    let codes: Vec<[u8; 3]> = view.painting.pixels.iter().map(|p| p.map(|x| (linear_to_srgb(x) * 255.0).round().clamp(0.0, 255.0) as u8)).collect();
    let mut levels = [0usize; 3];
    let mut bounds: Vec<(usize, [[f64; 2]; 3])> = samples.iter().map(|&k| (k, [[0.0, f64::INFINITY]; 3])).collect();
    let mut tables: Vec<Vec<u8>> = Vec::new();
    for c in 0..3 {
        let mut seen = [false; 256];
        for &k in &samples {
            seen[codes[k][c] as usize] = true;
        }
        let table: Vec<u8> = (0..=255u8).filter(|&v| seen[v as usize]).collect();
        levels[c] = table.len();
        tables.push(table);
    }
    if levels.iter().any(|&n| n > MAX_LEVELS) || levels.iter().all(|&n| n < MIN_LEVELS) {
        return None;
    }
    // The distance transforms run on the samples' bounding box (every tone, so every edge,
    // lies inside it), one tone per thread: a 512² painting of 6 levels takes 36 of them.
    let crop = Crop::around(&samples, w);
    let local: Vec<usize> = samples.iter().map(|&k| crop.local(k, w)).collect();
    for (c, table) in tables.iter().enumerate() {
        if table.len() < 2 {
            continue;
        }
        let mut index: Vec<Option<usize>> = vec![None; crop.w * crop.h];
        for (&k, &l) in samples.iter().zip(&local) {
            index[l] = Some(table.binary_search(&codes[k][c]).unwrap_or(0));
        }
        let value = |i: usize| table[i] as f64 / 255.0;
        // Per tone: each of its samples' reconstructed value and interval (sRGB code units).
        let tones: Vec<Vec<(usize, f64, [f64; 2])>> = (0..table.len())
            .into_par_iter()
            .map(|i| {
                let region: Vec<usize> = (0..samples.len()).filter(|&s| index[local[s]] == Some(i)).collect();
                if region.is_empty() {
                    return Vec::new();
                }
                let below = distance_to(&index.iter().map(|x| x.is_some_and(|j| j < i)).collect::<Vec<_>>(), crop.w, crop.h);
                let above = distance_to(&index.iter().map(|x| x.is_some_and(|j| j > i)).collect::<Vec<_>>(), crop.w, crop.h);
                // The edges' values: midpoints to the neighbouring levels, or half a step
                // beyond this level where there is no neighbour on that side.
                let step_lo = if i > 0 { value(i) - value(i - 1) } else { value(i + 1) - value(i) };
                let step_hi = if i + 1 < table.len() { value(i + 1) - value(i) } else { value(i) - value(i - 1) };
                let (lo, hi) = (value(i) - step_lo / 2.0, value(i) + step_hi / 2.0);
                let far = |d: &[f64]| region.iter().map(|&s| d[local[s]]).filter(|d| d.is_finite()).fold(0.0, f64::max).max(1.0);
                let (far_below, far_above) = (far(&below), far(&above));
                region
                    .iter()
                    .map(|&s| {
                        let (db, da) = (below[local[s]], above[local[s]]);
                        let x = match (db.is_finite(), da.is_finite()) {
                            (true, true) => lo + (hi - lo) * db / (db + da),
                            // The brightest region of its neighbourhood: from its lower edge up.
                            (true, false) => lo + (hi - lo) * (db / far_below),
                            (false, true) => hi - (hi - lo) * (da / far_above),
                            (false, false) => value(i),
                        };
                        (s, x, [lo, hi])
                    })
                    .collect()
            })
            .collect();
        for (s, x, [lo, hi]) in tones.into_iter().flatten() {
            view.painting.pixels[samples[s]][c] = srgb_to_linear(x.clamp(0.0, 1.0) as f32);
            bounds[s].1[c] = [lo, hi].map(|b| srgb_to_linear(b.clamp(0.0, 1.0) as f32) as f64);
        }
    }
    Some(Toned { levels, bounds })
}

/// Levels of a channel that [`refine`] reads as the luminance's shading, scaled and offset.
const FEW_LEVELS: usize = 3;

/// A toned sample for [`refine`]: pixel, proxy basis, light delivered, intervals.
type Site = (usize, [f64; proxy::BASIS], [f64; 3], [[f64; 2]; 3]);

/// The luminance's tones of a toned view under its geometry's light, and how well the
/// proxy and the best lobe family hold them ([`held`]); [`refine`] reads through it.
pub struct Luminance {
    geometry: Vec<Site>,
    shape: [f64; proxy::BASIS],
    family: Option<Family>,
    /// How far the proxy's Blinn-Phong lobes leave the intervals ([`outside`]).
    proxy_outside: f64,
    /// Per site of `geometry`, whether the family's reading misses its interval by more
    /// than [`OUTLIER_WIDTHS`] of it.
    outliers: Vec<bool>,
}

/// A site is left out of a tones' reading ([`refine`]'s) when the reading misses its
/// luminance interval by more than this many times the interval's width: a tone the shading
/// around it does not explain. In the faults study these are what the stray search left of
/// a stroke and the core of a highlight the brush brightened past every lobe. A reading is a
/// least-squares fit to the intervals, and a few such sites bend it for all the rest: a Ward
/// sphere in 6 flat tones with eight stray strokes was read through the Ashikhmin-Shirley
/// lobe, its tones left by 0.118; without its 74 outliers, through Phong's, left by 0.032.
/// One interval width: a site the shading explains lies within its interval, so a miss of a
/// whole width is not the reading's error but the site's (the sweep over the width is in
/// docs/notes/history.md, "Source comments"). The outliers keep their interpolation. The lights a toned view is judged under
/// ([`held`]) are judged on the first reading: judged on the second too, the eight seeds'
/// medians were the same, at a second reading per light judged.
const OUTLIER_WIDTHS: f64 = 1.0;

/// The toned samples of `view` still usable, as sites.
fn sites(view: &PaintedView, toned: &Toned) -> Vec<Site> {
    toned
        .bounds
        .iter()
        .filter(|&&(k, _)| view.geometry.usable[k])
        .filter_map(|&(k, b)| {
            let px = view.geometry.pixels[k].as_ref()?;
            Some((k, proxy::basis(px.query.l, px.query.v), px.light, b))
        })
        .collect()
}

/// `reading` read again without its outliers ([`OUTLIER_WIDTHS`]); as it is when it has
/// none.
fn without_outliers(view: &PaintedView, reading: Luminance) -> Luminance {
    if !reading.outliers.contains(&true) {
        return reading;
    }
    let kept: Vec<Site> = reading.geometry.iter().zip(&reading.outliers).filter(|(_, &o)| !o).map(|(s, _)| *s).collect();
    read(view, kept).unwrap_or(reading)
}

/// Whether `y` lies beyond interval `[lo, hi]` by more than [`OUTLIER_WIDTHS`] of its width.
fn beyond(y: f64, [lo, hi]: &[f64; 2]) -> bool {
    let slack = OUTLIER_WIDTHS * (hi - lo);
    y < lo - slack || y > hi + slack
}

/// A site's luminance interval: its channels' intervals weighted as luminance.
fn luminance_interval(bounds: &[[f64; 2]; 3]) -> [f64; 2] {
    [0, 1].map(|e| images::luminance(bounds.map(|b| b[e])))
}

/// The luminance's tones of `geometry`'s sites read by the proxy and the lobe families.
fn read(view: &PaintedView, geometry: Vec<Site>) -> Option<Luminance> {
    // The shape, from the luminance: S(l, v) times the luminance the light delivers.
    let luminance: Vec<([f64; proxy::BASIS], [f64; 2])> = geometry
        .iter()
        .map(|(_, b, light, bounds)| {
            let e = images::luminance(*light);
            (b.map(|x| x * e), luminance_interval(bounds))
        })
        .collect();
    let start: Vec<f64> = geometry.iter().map(|&(k, ..)| images::luminance(view.painting.pixels[k].map(f64::from))).collect();
    let (shape, _) = proxy::fit_within(&luminance, &start)?;
    let blinn: Vec<([f64; 4], [f64; 2])> =
        luminance.iter().map(|(b, i)| ([b[0], b[1], b[2], (3..proxy::BASIS).map(|j| shape[j] * b[j]).sum()], *i)).collect();
    let proxy_outside = outside(&blinn, &start, &[shape[0], shape[1], shape[2], 1.0]);
    let family = family(view, &geometry, &luminance, &start);
    let outliers = match &family {
        Some(f) => luminance.iter().zip(&f.shapes).map(|((b, interval), &shape)| beyond(proxy::eval(&family_basis(b, shape), &f.x), interval)).collect(),
        None => vec![false; geometry.len()],
    };
    Some(Luminance { geometry, shape, family, proxy_outside, outliers })
}

/// How a toned view's tones are held under the view's light ([`Luminance`]; `None` when
/// there is nothing to read). The tones are the painting's evidence: where the edges between
/// them lie is what the painter put down, unlike the interpolation between them ([`smooth`]),
/// so a light registered on the interpolation is checked on this ([`crate::read::Reader::read`]),
/// and the reading kept is passed on to [`refine`] for the light kept.
pub fn held(view: &PaintedView, toned: &Toned) -> Option<Luminance> {
    read(view, sites(view, toned))
}

impl Luminance {
    /// How far the best reading (the proxy's or a lobe family's) leaves the tone intervals
    /// ([`outside`], relative).
    pub fn outside(&self) -> f64 {
        self.family.as_ref().map_or(self.proxy_outside, |f| f.outside.min(self.proxy_outside))
    }
}

/// Reads a toned view, once its light is known (registered): the shading closest to the
/// painting's intervals (`toned.bounds`), starting from [`smooth`]'s interpolation, and each
/// pixel's value clamped into its interval. Where the shading explains the painting the tones
/// become it (the interpolation between edges is only a guess across a region a third of the
/// sphere wide); where it does not, the interpolation stays. Returns the lobe family and
/// width read through, or `None` for the physical proxy ([`super::proxy`]).
///
/// A channel with three or four levels does not pin seven functions down, so the shape is
/// read from the luminance first, whose intervals are narrow (it mixes every channel's edges,
/// and one material's channels share their shading): a lobe family's ([`family`]) unless the
/// proxy's Blinn-Phong lobes hold the tones clearly better ([`LOBE_MARGIN`]). Each channel
/// then fits only its own ambient, diffuse, cool-side and highlight weights on that shape.
/// `held`, when given, is [`held`]'s reading of this view under its current light (not
/// searched again). It is read again without its outliers ([`OUTLIER_WIDTHS`]), which
/// keep their interpolation, as every pixel the reading does not explain does.
pub fn refine(view: &mut PaintedView, toned: &Toned, held: Option<Luminance>) -> Option<(Lobe, f64)> {
    let reading = held.or_else(|| self::held(view, toned))?;
    let Luminance { geometry, shape, family: best, proxy_outside, .. } = without_outliers(view, reading);
    let value = |k: usize, c: usize| view.painting.pixels[k][c] as f64;
    // The family's lobe unless the proxy holds the tones clearly better; under a headlight,
    // only where the family holds them clearly better ([`LOBE_MARGIN`]).
    let headlit = crate::factor::headlit(geometry.iter().filter_map(|&(k, ..)| view.geometry.pixels[k].as_ref().map(|p| (p.query.l, p.query.v))));
    let gain = if headlit { 1.0 / LOBE_MARGIN } else { LOBE_MARGIN };
    let read = best.filter(|f| f.outside <= gain * proxy_outside);
    // Per site, per unit of light: the diffuse shape, the luminance's lobe and its whole
    // shading.
    let shading: Vec<(f64, f64, f64)> = match &read {
        Some(f) => geometry
            .iter()
            .zip(&f.shapes)
            .map(|(&(_, b, ..), &(d, s))| {
                let lobe = f.x[3] * s;
                (d, lobe, f.x[0] * b[0] + f.x[1] * d + f.x[2] * b[2] + lobe)
            })
            .collect(),
        None => geometry.iter().map(|(_, b, ..)| (b[1], (3..proxy::BASIS).map(|j| shape[j] * b[j]).sum(), proxy::eval(b, &shape))).collect(),
    };
    let mut out: Vec<[f32; 3]> = geometry.iter().map(|&(k, ..)| view.painting.pixels[k]).collect();
    for c in 0..3 {
        if toned.levels[c] < 2 {
            continue;
        }
        // Per channel: ambient, max(n.l, 0), min(n.l, 0), and the luminance's highlight;
        // a channel of two or three tones has one or two edges, too few for four weights,
        // and takes the luminance's whole shading, scaled and offset.
        let few = toned.levels[c] <= FEW_LEVELS;
        let points: Vec<([f64; 4], [f64; 2])> = geometry
            .iter()
            .zip(&shading)
            .map(|((_, b, light, bounds), &(diffuse, lobe, whole))| {
                let basis = if few { [b[0], whole, 0.0, 0.0] } else { [b[0], diffuse, b[2], lobe] };
                (basis.map(|x| x * light[c]), bounds[c])
            })
            .collect();
        let start: Vec<f64> = geometry.iter().map(|&(k, ..)| value(k, c)).collect();
        let Some((x, t)) = proxy::fit_within(&points, &start) else { continue };
        // Where the proxy still leaves a pixel's interval (by more than a quarter of it) it
        // does not explain the painting there (a highlight sharper than its lobes): the
        // interpolation stays.
        for (i, (&(b, [lo, hi]), y)) in points.iter().zip(&t).enumerate() {
            let f = proxy::eval(&b, &x);
            let slack = 0.25 * (hi - lo);
            if f >= lo - slack && f <= hi + slack {
                out[i][c] = *y as f32;
            }
        }
    }
    for (&(k, ..), px) in geometry.iter().zip(out) {
        view.painting.pixels[k] = px;
    }
    read.map(|f| (f.lobe, f.alpha))
}

/// Widths [`family`] tries per lobe family, log-spaced.
const ALPHAS: usize = 16;
const ALPHA_MIN: f64 = 0.02;
const ALPHA_MAX: f64 = 1.0;
/// At most this many toned samples (every k-th) in [`family`]'s search over widths.
const SEARCH_SAMPLES: usize = 8192;

/// How far a proxy leaves the intervals: $\sqrt{\sum w^2 d^2 / \sum w^2 s^2}$ with $d$ the
/// distance of the proxy to each interval (0 inside), $s$ the start and $w$ relative
/// weights, as in [`proxy::fit_within`].
fn outside<const N: usize>(points: &[([f64; N], [f64; 2])], start: &[f64], x: &[f64; N]) -> f64 {
    let peak = start.iter().copied().fold(0.0, f64::max);
    let (mut r, mut t) = (0.0, 0.0);
    for ((b, [lo, hi]), &s) in points.iter().zip(start) {
        let d = distance_outside(proxy::eval(b, x), [*lo, *hi]);
        let w = 1.0 / (s + 0.05 * peak);
        r += (w * d).powi(2);
        t += (w * s).powi(2);
    }
    (r / t.max(f64::MIN_POSITIVE)).sqrt()
}

/// How far `y` lies outside interval `[lo, hi]` (0 inside it).
pub(super) fn distance_outside(y: f64, [lo, hi]: [f64; 2]) -> f64 {
    if y < lo {
        lo - y
    } else if y > hi {
        y - hi
    } else {
        0.0
    }
}

/// A site's basis for a lobe family's reading: ambient, the family's diffuse shape `d`, the
/// cool side and its lobe `s` at unit weight, from the site's proxy basis `b` (scaled by the
/// light delivered).
fn family_basis(b: &[f64; proxy::BASIS], (d, s): (f64, f64)) -> [f64; 4] {
    [b[0], b[0] * d, b[2], b[0] * s]
}

/// A lobe family's reading of the luminance's tones: the family, its width, and per site
/// (per unit of light) its diffuse shape and its lobe at unit weight.
struct Family {
    lobe: Lobe,
    alpha: f64,
    /// Weights of ambient, diffuse, cool side and lobe.
    x: [f64; 4],
    /// How far it leaves the intervals ([`outside`]).
    outside: f64,
    shapes: Vec<(f64, f64)>,
}

/// The luminance's tones read with the lobe of a classic family ([`Lobe`], the base's:
/// GGX, Blinn-Phong, Phong, Ward, Ashikhmin-Shirley, Oren-Nayar, Minnaert) instead of the
/// proxy's Blinn-Phong lobes: ambient, the family's diffuse shape, the cool side and its
/// lobe, of the width that best keeps inside the intervals; of the families, the one that
/// leaves them least. [`refine`] reads through it unless the Blinn-Phong lobes hold the
/// tones clearly better ([`LOBE_MARGIN`]). Six levels pin a lobe's shape down well: fitted
/// to the intervals alone, each of the nine faults-study models but Lambert's is held best by its own family
/// (a GGX sphere of α = 0.04 leaves its intervals by 0.11 through the Blinn-Phong lobes,
/// 0.0005 through its own; an Oren-Nayar one 0.012 and 0.0007). A Lambertian sphere is held
/// by any lobe at small weight, and by the proxy, equally.
fn family(
    view: &PaintedView,
    geometry: &[Site],
    luminance: &[([f64; proxy::BASIS], [f64; 2])],
    start: &[f64],
) -> Option<Family> {
    let dirs: Vec<Option<(glam::DVec3, glam::DVec3)>> =
        geometry.iter().map(|&(k, ..)| view.geometry.pixels[k].as_ref().map(|p| (p.query.l, p.query.v))).collect();
    let shapes = |lobe: Lobe, alpha: f64, idx: &[usize]| -> Vec<(f64, f64)> {
        idx.iter()
            .map(|&i| {
                let (d, s, _) = dirs[i].map_or((0.0, 0.0, 0.0), |(l, v)| lobe.shape(l, v, alpha));
                (d, s)
            })
            .collect()
    };
    // b[0] is the basis's 1 times the luminance the light delivers.
    let points = |shapes: &[(f64, f64)], idx: &[usize]| -> Vec<([f64; 4], [f64; 2])> {
        idx.iter()
            .zip(shapes)
            .map(|(&i, &(d, s))| {
                let (b, interval) = &luminance[i];
                (family_basis(b, (d, s)), *interval)
            })
            .collect()
    };
    let stride = luminance.len().div_ceil(SEARCH_SAMPLES).max(1);
    let search: Vec<usize> = (0..luminance.len()).step_by(stride).collect();
    let search_start: Vec<f64> = search.iter().map(|&i| start[i]).collect();
    let candidates: Vec<(Lobe, f64)> = Lobe::ALL
        .iter()
        .flat_map(|&lobe| {
            let widths = if lobe.has_width() { ALPHAS } else { 1 };
            (0..widths).map(move |k| (lobe, if lobe.has_width() { ALPHA_MIN * (ALPHA_MAX / ALPHA_MIN).powf(k as f64 / (ALPHAS - 1) as f64) } else { 1.0 }))
        })
        .collect();
    // Each candidate on its own thread; the least outside wins, the first of equals.
    let (_, _, lobe, alpha) = candidates
        .par_iter()
        .enumerate()
        .filter_map(|(n, &(lobe, alpha))| {
            let pts = points(&shapes(lobe, alpha, &search), &search);
            proxy::fit_within(&pts, &search_start).map(|(x, _)| (outside(&pts, &search_start, &x), n, lobe, alpha))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))?;
    let all: Vec<usize> = (0..luminance.len()).collect();
    let shapes = shapes(lobe, alpha, &all);
    let pts = points(&shapes, &all);
    let (x, _) = proxy::fit_within(&pts, start)?;
    Some(Family { lobe, alpha, x, outside: outside(&pts, start, &x), shapes })
}

/// [`refine`] reads the tones through the best lobe family unless the proxy's Blinn-Phong
/// lobes leave the intervals this many times less; under a headlight, only where the family
/// leaves them this many times less than the proxy. A physical family is the better guess
/// where the painting has no tones to say, and brush texture moves the tone edges so that
/// every family and the proxy hold them about equally. Under a headlight every family holds
/// the tones through some function of the one angle the painting shows, and which one is
/// read decides the material under every other light: there the family only when clearly
/// better, by this factor (the study behind both is in docs/notes/history.md, "Source
/// comments").
const LOBE_MARGIN: f64 = 2.0;

/// A rectangle of an image `w` pixels wide: the bounding box of some of its pixels.
struct Crop {
    x0: usize,
    y0: usize,
    w: usize,
    h: usize,
}

impl Crop {
    /// The bounding box of `pixels` (not empty) of an image `w` wide.
    fn around(pixels: &[usize], w: usize) -> Crop {
        let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
        for &k in pixels {
            let (x, y) = (k % w, k / w);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
        Crop { x0, y0, w: x1 + 1 - x0, h: y1 + 1 - y0 }
    }

    /// Pixel `k` of the image (inside the box) as an index into the box.
    fn local(&self, k: usize, w: usize) -> usize {
        (k / w - self.y0) * self.w + (k % w - self.x0)
    }
}

/// Euclidean distance from each pixel to the nearest `set` pixel (infinite when there is
/// none): the exact transform of Felzenszwalb and Huttenlocher (2012), by rows then columns.
fn distance_to(set: &[bool], w: usize, h: usize) -> Vec<f64> {
    const FAR: f64 = 1e20;
    let mut d: Vec<f64> = set.iter().map(|&s| if s { 0.0 } else { FAR }).collect();
    let mut line = Vec::new();
    for j in 0..h {
        line.clear();
        line.extend_from_slice(&d[j * w..(j + 1) * w]);
        let out = transform_1d(&line);
        d[j * w..(j + 1) * w].copy_from_slice(&out);
    }
    for i in 0..w {
        line.clear();
        line.extend((0..h).map(|j| d[j * w + i]));
        let out = transform_1d(&line);
        for (j, x) in out.into_iter().enumerate() {
            d[j * w + i] = x;
        }
    }
    d.into_iter().map(|x| if x >= FAR / 2.0 { f64::INFINITY } else { x.sqrt() }).collect()
}

/// The 1D squared distance transform of sampled function `f` (lower envelope of parabolas).
fn transform_1d(f: &[f64]) -> Vec<f64> {
    let n = f.len();
    if n == 0 {
        return Vec::new();
    }
    let mut out = vec![0.0; n];
    let mut v = vec![0usize; n];
    let mut z = vec![0.0f64; n + 1];
    let mut k = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let parabola = |q: usize, p: usize| ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q as f64 - p as f64));
    for q in 1..n {
        // z[0] is -inf, so this stops at k = 0 at the latest.
        let mut s = parabola(q, v[k]);
        while s <= z[k] {
            k -= 1;
            s = parabola(q, v[k]);
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    let mut k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *o = (q as f64 - p as f64).powi(2) + f[p];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_are_euclidean() {
        // One set pixel at (2, 1) in a 5x4 grid.
        let mut set = vec![false; 20];
        set[5 + 2] = true;
        let d = distance_to(&set, 5, 4);
        for j in 0..4 {
            for i in 0..5 {
                let e = ((i as f64 - 2.0).powi(2) + (j as f64 - 1.0).powi(2)).sqrt();
                assert!((d[j * 5 + i] - e).abs() < 1e-12, "({i}, {j}): {} vs {e}", d[j * 5 + i]);
            }
        }
        assert!(distance_to(&[false; 6], 3, 2).iter().all(|x| x.is_infinite()));
    }
}
