//! The key light of a lit-sphere picture: the direction (anywhere but straight behind the
//! sphere, [`MIN_LIGHT_Z`]) whose Lambertian shading, with a robust weight, best explains
//! the disk's luminance, and how sure that is ([`estimate_light`]); for a stylized picture,
//! the direction in front its tone edges and highlight are drawn about
//! ([`estimate_tone_light`]); how much light the unlit side gets ([`unlit_floor`]).

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::Disk;
use crate::error::{Error, Result};
use crate::images::Painting;

/// The estimated key light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightEstimate {
    /// Unit direction towards the light, view frame (x right, y up, z to the viewer).
    pub direction: DVec3,
    /// Angle within which other directions explain the shading almost as well (their cost
    /// within 10% of the best), degrees: small means sure.
    pub spread_deg: f64,
    /// Fraction of the disk's pixels the shading model explains (the rest: highlights,
    /// strokes, rim lights).
    pub inliers: f64,
    /// The picture cannot decide the light (directions over [`UNDECIDED_DEG`] apart explain
    /// it as well): the direction is the plausible key light among them ([`estimate_light`]).
    pub undecided: bool,
    /// The light is behind the sphere ($l_z < 0$): more than half of what the picture shows
    /// faces away from it, lit by what is not the key light ([`unlit_floor`]).
    pub behind: bool,
}

/// Rec. 709 luminance of linear RGB.
fn luminance(c: &[f32; 3]) -> f64 {
    crate::images::luminance(c.map(f64::from))
}

/// Directions with $l_z \ge$ `min_z`, about evenly spread (a Fibonacci spiral of `n` points
/// over the whole sphere, those kept).
fn search_directions(n: usize, min_z: f64) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * k as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .filter(|d| d.z >= min_z)
        .collect()
}

/// The search's reach behind the sphere: every direction but those within 25° of straight
/// behind ($l_z \ge -\cos 25°$). A light within 18° of straight behind lights none of the
/// disk the estimate samples (normals out to 0.95 of the radius, [`disk_samples`]), so
/// nothing there can be told apart; 25° leaves a lit crescent a few pixels wide.
pub const MIN_LIGHT_Z: f64 = -0.906;

/// A direction explains the shading "as well" as the best when its cost is within this
/// factor of the best's: the misfit of a painted or environment-lit sphere is structured
/// (strokes, reflections), not pixel noise, so a 10% change is the smallest that shows.
const AS_WELL: f64 = 1.1;

/// The picture cannot decide the light when directions this far apart (degrees) explain
/// it as well: a sphere under one key light pins it to a few degrees (rendered spheres:
/// under 15°, tests/lit_sphere.rs); a MatCap lit by its surroundings leaves a wide region.
pub const UNDECIDED_DEG: f64 = 30.0;

/// The plausible key light when the picture cannot decide: from the upper front (45° above
/// the view), the photographer's and painter's default.
pub const KEY: DVec3 = DVec3::new(0.0, std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::FRAC_1_SQRT_2);

/// Concentration of the prior around [`KEY`] (von Mises–Fisher): broad, about 40° wide, so
/// among directions that explain the picture as well it prefers the upper front without
/// putting every undecided picture on the same point.
const KEY_CONCENTRATION: f64 = 2.0;

/// Width of the likelihood in relative cost: a direction [`AS_WELL`] from the best weighs
/// $e^{-2}$ of it.
const COST_WIDTH: f64 = 0.05;

/// Weighted least-squares cost of the shading model under light `l` (module docs), with
/// its coefficients; `None` when the fit would need light to darken the lit side.
fn model_cost(l: DVec3, normals: &[DVec3], y: &[f64], weight: &[f64]) -> Option<(f64, [f64; 3])> {
    // One pass of sums: the features are (1, c⁺, c⁻) with c⁺ c⁻ = 0, so the normal equations
    // and the cost need only these nine (the search makes thousands of passes per picture).
    let mut t = [0.0f64; 9];
    for ((n, &yv), &wt) in normals.iter().zip(y).zip(weight) {
        let c = n.dot(l);
        let (p, m) = (c.max(0.0), c.min(0.0));
        let terms = [1.0, p, m, p * p, m * m, yv, yv * p, yv * m, yv * yv];
        for (s, x) in t.iter_mut().zip(terms) {
            *s += wt * x;
        }
    }
    let solve = |cols: usize| -> Option<(f64, [f64; 3])> {
        let keep = if cols == 2 { 0.0 } else { 1.0 };
        let gram = DMat3::from_cols(DVec3::new(t[0], t[1], t[2] * keep), DVec3::new(t[1], t[3], 0.0), DVec3::new(t[2] * keep, 0.0, t[4] * keep));
        let rhs = DVec3::new(t[5], t[6], t[7] * keep);
        // A tiny ridge: with the light at the viewer no pixel is unlit and c has no data.
        let mut m = gram + DMat3::from_diagonal(DVec3::splat(1e-9 * (t[0] + 1.0)));
        if cols == 2 {
            m.z_axis.z = 1.0;
        }
        let s = m.inverse() * rhs;
        if !s.is_finite() || s.y < 0.0 {
            return None;
        }
        // Σ w (f·s − y)², from the same sums.
        let cost = (s.dot(gram * s) - 2.0 * s.dot(rhs) + t[8]).max(0.0);
        Some((cost, s.to_array()))
    };
    match solve(3) {
        Some((cost, s)) if s[2] >= 0.0 => Some((cost, s)),
        _ => solve(2),
    }
}

/// Estimates the key light of a lit sphere (module docs). At most 4000 disk pixels are used.
/// When directions more than [`UNDECIDED_DEG`] apart explain the shading as well, the
/// picture cannot decide: the estimate is the mean of those directions weighted by how well
/// they explain it and by a broad prior around the upper front ([`KEY`]), and `undecided`.
pub fn estimate_light(p: &Painting, disk: &Disk) -> Result<LightEstimate> {
    let (normals, y) = disk_samples(p, disk, 4000)?;
    let coarse = search_directions(6000, MIN_LIGHT_Z);
    let (mut best, mut cost, weight) = robust_best(&coarse, &normals, &y)?;
    // Refine in a cap of 4° around the best.
    let fine: Vec<DVec3> = cap(best, 4f64.to_radians(), 600, MIN_LIGHT_Z);
    let costs = |dirs: &[DVec3]| -> Vec<(DVec3, f64)> { dirs.iter().filter_map(|&l| model_cost(l, &normals, &y, &weight).map(|(c, _)| (l, c))).collect() };
    let mut scored = costs(&coarse);
    scored.extend(costs(&fine));
    if let Some(&(b, c)) = scored.iter().min_by(|a, b| a.1.total_cmp(&b.1)) {
        if c < cost {
            (best, cost) = (b, c);
        }
    }
    let inliers = weight.iter().sum::<f64>() / weight.len() as f64;
    Ok(settle(scored, best, cost, inliers))
}

/// The estimate from every direction `scored` (with its cost; `best` the least, `cost`
/// its cost): the directions that explain the picture [`AS_WELL`] give the spread, and
/// when they are over [`UNDECIDED_DEG`] apart the picture cannot decide and the direction
/// is the plausible key light among them ([`key_light`]).
fn settle(scored: Vec<(DVec3, f64)>, best: DVec3, cost: f64, inliers: f64) -> LightEstimate {
    let plausible: Vec<(DVec3, f64)> = scored.into_iter().filter(|(_, c)| *c <= AS_WELL * cost).collect();
    let widest = |d: DVec3| plausible.iter().map(|(l, _)| l.angle_between(d)).fold(0.0f64, f64::max);
    let undecided = widest(best).to_degrees() > UNDECIDED_DEG;
    let direction = if undecided { key_light(&plausible, cost) } else { best };
    let behind = direction.z < 0.0;
    LightEstimate { direction, spread_deg: widest(direction).to_degrees(), inliers, undecided, behind }
}

/// The key light of a stylized picture: the direction under which its luminance is what
/// the factored model draws, a function of $n \cdot l$ plus one of $n \cdot h$ (the
/// terminator and the highlight: $p\,q$ of eq. 3.1, added in display codes; the view's
/// $r(n \cdot v)$ does not depend on the light, and given the freedom it takes concentric
/// tones from $p$), whatever those functions are (two tones, three, a gradient). The cost of a
/// direction is what that model leaves unexplained, each function taken as the mean over
/// thin bands ([`TONE_BANDS`]) by backfitting; a picture whose tone edges are circles about
/// $l$ and whose highlight is a circle about $h$ scores near zero there, and every direction
/// off it cuts tones across bands. At most 16000 disk pixels are used, their luminance in
/// sRGB codes; the spread and the undecided case are as in [`estimate_light`], and
/// `inliers` is the share of the luminance's variance the model explains.
pub fn estimate_tone_light(p: &Painting, disk: &Disk) -> Result<LightEstimate> {
    let (normals, linear) = disk_samples(p, disk, 16000)?;
    // In display codes, where the painter chose the tones.
    let y: Vec<f64> = linear.iter().map(|&v| f64::from(crate::images::linear_to_srgb(v as f32))).collect();
    let cost = |l: DVec3| band_residual(l, 1.0, &normals, &y);
    // In front only: a tone edge is a circle about $l$ and about $-l$ alike.
    let coarse = search_directions(4000, 0.0);
    let mut scored: Vec<(DVec3, f64)> = coarse.par_iter().map(|&l| (l, cost(l))).collect();
    let least = |scored: &[(DVec3, f64)]| scored.iter().copied().min_by(|a, b| a.1.total_cmp(&b.1)).ok_or_else(|| Error::input("no light explains the sphere's tones"));
    let (coarse_best, _) = least(&scored)?;
    let fine = cap(coarse_best, 5f64.to_radians(), 600, 0.0);
    scored.extend(fine.par_iter().map(|&l| (l, cost(l))).collect::<Vec<_>>());
    let (best, residual) = least(&scored)?;
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let total = y.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>();
    let inliers = if total > 0.0 { (1.0 - residual / total).clamp(0.0, 1.0) } else { 1.0 };
    Ok(settle(scored, best, residual, inliers))
}

/// The light that reaches the side of `p`'s sphere the key light `l` does not, as a fraction
/// of the lit side: the shading model $a + b^+ c^+ + b^- c^-$ fitted robustly under `l`
/// (as [`estimate_light`] fits it), its value at $n \cdot l = -1$ over its value at
/// $n \cdot l = 1$, in $[0, 1]$. Under a light behind the sphere the picture shows that side
/// directly: the light prior's floor is then the picture's ([`crate::litsphere::light_floor`]).
pub fn unlit_floor(p: &Painting, disk: &Disk, l: DVec3) -> Result<f64> {
    let (normals, y) = disk_samples(p, disk, 4000)?;
    let (_, _, weight) = robust_best(&[l], &normals, &y)?;
    let s = model_cost(l, &normals, &y, &weight).map_or([0.0; 3], |(_, s)| s);
    let lit = s[0] + s[1];
    Ok(if lit > 0.0 { ((s[0] - s[2]) / lit).clamp(0.0, 1.0) } else { 0.0 })
}

/// Angular radius of an environment's key light, degrees: a window or a softbox about a
/// metre across at three metres, the key of studio MatCaps and HDR environments.
pub const ENVIRONMENT_KEY_DEG: f64 = 10.0;

/// The angular radius of a picture's key light, degrees, from the light its unlit side shows
/// (`unlit`, [`unlit_floor`]): above the prior's floor (`floor`), the picture was lit by its
/// surroundings, whose key light is an area of them ([`ENVIRONMENT_KEY_DEG`]); where that
/// side is dark, one compact light, a point (0). The size cannot be read from the
/// terminator itself: a BRDF's own falloff towards grazing (a rough or coated base) softens it
/// as much. A point light's corner at the terminator, taken by the light prior as its shape
/// for a picture whose terminator is soft, showed as a crease along it on every model.
pub fn light_size(unlit: f64, floor: f64) -> f64 {
    if unlit > floor {
        ENVIRONMENT_KEY_DEG
    } else {
        0.0
    }
}

/// Bands of a cosine in $[-1, 1]$ for [`estimate_tone_light`]: 0.0125 wide, so a tone edge
/// of a 256-pixel disk crosses a band within a few pixels, and 16000 pixels put about 60 in
/// each band the disk reaches.
const TONE_BANDS: usize = 160;

/// Backfitting sweeps of [`band_residual`]: the second settles what the first split
/// between the terminator's bands and the highlight's; more change the cost by little.
const SWEEPS: usize = 2;

/// $\sum$ of squared residuals of $y \approx P(n \cdot l) + Q(n \cdot h_k)$ with $P, Q$
/// piecewise constant over [`TONE_BANDS`] bands, fitted by backfitting; $h_k$ is the half
/// vector leaned by `lean` ([`crate::factor::leaned_half`]; the view is the lit sphere's,
/// $v = +z$).
fn band_residual(l: DVec3, lean: f64, normals: &[DVec3], y: &[f64]) -> f64 {
    let h = crate::factor::leaned_half(l, DVec3::Z, lean);
    let bands: Vec<[usize; 2]> = normals.iter().map(|n| [tone_band(n.dot(l)), tone_band(n.dot(h))]).collect();
    let mut parts = vec![[0.0f64; 2]; y.len()];
    for _ in 0..SWEEPS {
        for f in 0..2 {
            let (mut sum, mut count) = ([0.0f64; TONE_BANDS], [0usize; TONE_BANDS]);
            for ((b, part), &v) in bands.iter().zip(&parts).zip(y) {
                sum[b[f]] += v - part[1 - f];
                count[b[f]] += 1;
            }
            for (b, part) in bands.iter().zip(parts.iter_mut()) {
                part[f] = sum[b[f]] / count[b[f]] as f64;
            }
        }
    }
    parts.iter().zip(y).map(|(part, &v)| (v - part.iter().sum::<f64>()).powi(2)).sum()
}

/// The band of [`TONE_BANDS`] a cosine in $[-1, 1]$ falls in.
fn tone_band(c: f64) -> usize {
    (((c + 1.0) * 0.5 * TONE_BANDS as f64) as usize).min(TONE_BANDS - 1)
}

/// Leans tried for a drawn highlight ([`highlight_lean`]): $2^{i/16}$ from 1/8 (the
/// highlight almost at the light) to 8 (almost at the view).
const LEANS: std::ops::RangeInclusive<i32> = -48..=48;

/// A highlight pixel stands this many robust standard deviations above the light's bands:
/// under Gaussian scatter 3σ passes one pixel in 700, so a flat tone's JPEG noise does not
/// make a highlight.
const HIGHLIGHT_SIGMAS: f64 = 3.0;

/// A drawn highlight's pixels lie within this angle of its brightest one (a dot or a window
/// is a few degrees across; a rim light elsewhere on the disk is not part of it).
const HIGHLIGHT_REACH_DEG: f64 = 20.0;

/// Where the painter put the highlight of a stylized picture lit from `l`: the lean $k$ of
/// the half vector $h_k \propto l + k v$ about which it is drawn (1: the physical half
/// vector; painters often put it nearer the light). The highlight is what the light's bands
/// leave: pixels [`HIGHLIGHT_SIGMAS`] above the picture as a function of $n \cdot l$, within
/// [`HIGHLIGHT_REACH_DEG`] of the brightest; $k$ puts $h_k$ at their centre. It is kept when
/// the Bayesian information criterion prefers it (one more parameter: $N \ln(c_1 / c_k) >
/// \ln N$ for $N$ pixels and [`band_residual`]'s costs, the residual taken as Gaussian), so a
/// picture whose highlight sits at $h$, or that has none, keeps 1.
pub fn highlight_lean(p: &Painting, disk: &Disk, l: DVec3) -> Result<f64> {
    let (normals, linear) = disk_samples(p, disk, 16000)?;
    let y: Vec<f64> = linear.iter().map(|&v| f64::from(crate::images::linear_to_srgb(v as f32))).collect();
    let Some(centre) = highlight_centre(l, &normals, &y) else { return Ok(1.0) };
    let angle = |k: f64| crate::factor::leaned_half(l, DVec3::Z, k).angle_between(centre);
    let lean = LEANS.map(|i| 2f64.powf(f64::from(i) / 16.0)).min_by(|a, b| angle(*a).total_cmp(&angle(*b))).unwrap_or(1.0);
    let (physical, leaned) = (band_residual(l, 1.0, &normals, &y), band_residual(l, lean, &normals, &y));
    let n = y.len() as f64;
    Ok(if leaned > 0.0 && n * (physical / leaned).ln() > n.ln() { lean } else { 1.0 })
}

/// The centre (a unit normal) of the pixels the light's bands leave bright
/// ([`highlight_lean`]), or `None` when fewer than three stand out.
fn highlight_centre(l: DVec3, normals: &[DVec3], y: &[f64]) -> Option<DVec3> {
    let bands: Vec<usize> = normals.iter().map(|n| tone_band(n.dot(l))).collect();
    let (mut sum, mut count) = ([0.0f64; TONE_BANDS], [0usize; TONE_BANDS]);
    for (&b, &v) in bands.iter().zip(y) {
        sum[b] += v;
        count[b] += 1;
    }
    let residual: Vec<f64> = bands.iter().zip(y).map(|(&b, &v)| v - sum[b] / count[b] as f64).collect();
    let mut abs: Vec<f64> = residual.iter().map(|r| r.abs()).collect();
    abs.sort_by(f64::total_cmp);
    // At least one 8-bit code: flat tones leave no scatter.
    let sigma = (1.4826 * abs[abs.len() / 2]).max(1.0 / 255.0);
    // The highlight is the brightest tone: within a flat tone's scatter of the brightest code.
    let brightest = y.iter().cloned().fold(0.0, f64::max) - super::style::TONE_WIDTH as f64 / 255.0;
    let stands = |k: usize| residual[k] > HIGHLIGHT_SIGMAS * sigma && y[k] >= brightest;
    let (peak, _) = residual.iter().enumerate().filter(|&(k, _)| stands(k)).max_by(|a, b| a.1.total_cmp(b.1))?;
    let reach = HIGHLIGHT_REACH_DEG.to_radians().cos();
    let bright: Vec<(DVec3, f64)> = (0..y.len()).filter(|&k| stands(k) && normals[k].dot(normals[peak]) >= reach).map(|k| (normals[k], residual[k])).collect();
    (bright.len() >= 3).then(|| bright.iter().map(|&(n, r)| n * r).sum::<DVec3>().normalize())
}

/// The disk's normals and luminances, off the rim (where normals are steep and edges mix
/// with the background), on a grid of at most about `most` pixels.
fn disk_samples(p: &Painting, disk: &Disk, most: usize) -> Result<(Vec<DVec3>, Vec<f64>)> {
    let (mut normals, mut y) = (Vec::new(), Vec::new());
    let total = (std::f64::consts::PI * disk.r * disk.r) as usize;
    let stride = ((total as f64 / most as f64).sqrt().floor() as usize).max(1);
    for j in (0..p.height).step_by(stride) {
        for i in (0..p.width).step_by(stride) {
            let k = j * p.width + i;
            if p.alpha[k] <= 0.0 {
                continue;
            }
            if let Some(n) = disk.normal(i, j, 0.95) {
                normals.push(n);
                y.push(luminance(&p.pixels[k]));
            }
        }
    }
    if normals.len() < 32 {
        return Err(Error::input("the sphere is too small or too transparent to estimate its light"));
    }
    Ok((normals, y))
}

/// The best of `dirs` under the shading model, with pixels the model misses by far
/// (highlights, strokes, rim lights: residuals beyond 2.5 MAD) left out so they stop pulling
/// the light towards them: its direction, cost and the pixels' weights.
fn robust_best(dirs: &[DVec3], normals: &[DVec3], y: &[f64]) -> Result<(DVec3, f64, Vec<f64>)> {
    let best_of = |weight: &[f64]| -> Result<(DVec3, f64, [f64; 3])> {
        dirs.iter()
            .filter_map(|&l| model_cost(l, normals, y, weight).map(|(c, s)| (l, c, s)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .ok_or_else(|| Error::input("no light explains the sphere's shading"))
    };
    let mut weight = vec![1.0; normals.len()];
    let (mut best, mut cost, mut coef) = best_of(&weight)?;
    for _ in 0..3 {
        let residual: Vec<f64> = normals
            .iter()
            .zip(y)
            .map(|(n, &yv)| {
                let c = n.dot(best);
                coef[0] + coef[1] * c.max(0.0) + coef[2] * c.min(0.0) - yv
            })
            .collect();
        // The scale from the pixels at or below the model only: a highlight only adds light
        // (specular over diffuse), so a glossy lobe's broad tail inflates the spread above
        // the prediction and, measured on both sides, would pass as shading and bend the
        // light towards it; below the prediction the spread is the shading's own.
        let mut abs: Vec<f64> = residual.iter().filter(|&&r| r >= 0.0).copied().collect();
        if abs.len() < 8 {
            abs = residual.iter().map(|r| r.abs()).collect();
        }
        abs.sort_by(f64::total_cmp);
        // At least one 8-bit code step at the top of the picture's range: a flat unlit side
        // (a rendered sphere's black) has no spread, and the lit side's quantization is not a
        // stroke.
        let sigma = (1.4826 * abs[abs.len() / 2]).max(y.iter().cloned().fold(0.0, f64::max) / 255.0);
        weight = residual.iter().map(|r| if r.abs() <= 2.5 * sigma { 1.0 } else { 0.0 }).collect();
        (best, cost, coef) = best_of(&weight)?;
    }
    Ok((best, cost, weight))
}

/// The mean of the `plausible` directions in front of the sphere (all of them when none is)
/// weighted by $e^{-(c/c_{best} - 1)/w}$ ([`COST_WIDTH`]) times the prior
/// $e^{\kappa (l \cdot K - 1)}$ ([`KEY`], [`KEY_CONCENTRATION`]): a posterior mean,
/// continuous in the picture. A picture that cannot decide its light is taken as lit from
/// where a key light is put, in front: behind, it would show little of its material.
fn key_light(plausible: &[(DVec3, f64)], best: f64) -> DVec3 {
    let any_front = plausible.iter().any(|(l, _)| l.z >= 0.0);
    let sum: DVec3 = plausible
        .iter()
        .filter(|(l, _)| l.z >= 0.0 || !any_front)
        .map(|&(l, c)| l * (-(c / best.max(1e-300) - 1.0) / COST_WIDTH + KEY_CONCENTRATION * (l.dot(KEY) - 1.0)).exp())
        .sum();
    let mean = sum.normalize_or(KEY);
    // On the same side as the candidates, as a mean of them is (up to rounding).
    DVec3::new(mean.x, mean.y, if any_front { mean.z.max(0.0) } else { mean.z.max(MIN_LIGHT_Z) }).normalize()
}

/// About `n` directions within `angle` of `centre`, with $l_z \ge$ `min_z`.
fn cap(centre: DVec3, angle: f64, n: usize, min_z: f64) -> Vec<DVec3> {
    let (t, b) = centre.any_orthonormal_pair();
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let cos_max = angle.cos();
    (0..n)
        .map(|k| {
            let z = 1.0 - (1.0 - cos_max) * (k as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * k as f64;
            (centre * z + t * r * phi.cos() + b * r * phi.sin()).normalize()
        })
        .filter(|d| d.z >= min_z)
        .collect()
}

/// The shading profile of `p`'s sphere under the light `l`: for each band of $n \cdot l$
/// ([`TONE_BANDS`]) up to [`PROFILE_TOP`] with 8 pixels or more, from the farthest from
/// the light, the median luminance of its pixels (sRGB, 0 to 1) and their number.
pub fn shading_profile(p: &Painting, disk: &Disk, l: DVec3) -> Vec<(f64, usize)> {
    let Ok((normals, linear)) = disk_samples(p, disk, 16000) else { return Vec::new() };
    let mut bands: Vec<Vec<f64>> = vec![Vec::new(); TONE_BANDS];
    for (n, &v) in normals.iter().zip(&linear) {
        let c = n.dot(l);
        if c <= PROFILE_TOP {
            bands[tone_band(c)].push(f64::from(crate::images::linear_to_srgb(v as f32)));
        }
    }
    bands
        .iter_mut()
        .filter(|b| b.len() >= 8)
        .map(|b| {
            b.sort_by(f64::total_cmp);
            (b[b.len() / 2], b.len())
        })
        .collect()
}

/// Largest $n \cdot l$ of [`shading_profile`]: a highlight drawn about the light lies above,
/// and would take the bands there whole.
const PROFILE_TOP: f64 = 0.9;
