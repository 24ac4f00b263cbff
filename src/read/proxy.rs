//! The physical proxy (issue 11): a small linear basis of plausible shading that a painting
//! is read against before the factored fit.
//!
//! The factored product $p(l)\,q(h)\,r(v)$ is too free on one view to say what a painting
//! *means*: it follows a misplaced light, a staircase of flat tones or a stray stroke as
//! readily as the shading. Seven functions of the light and view directions are not:
//! ambient, $\max(n\cdot l, 0)$, $\min(n\cdot l, 0)$ (a Gooch painting's cool side) and
//! Blinn-Phong lobes $(n\cdot h)^e\,(n\cdot l)$, $e$ = 4, 16, 64, 256 (the
//! cosine makes them shading, not BRDF, lobes: a Blinn-Phong painting is in the span). Their isophotes are circles about
//! $l$ and their highlight sits at $h$; fitted by linear least squares with relative weights
//! (dark and bright regions count alike, as in the relative RMS a fit reports), they give
//! the smooth shading a painting suggests. [`super::register`] finds the painter's light
//! with it; [`super::tones`] reads flat tones through it.

use glam::DVec3;

/// Functions in the basis.
pub const BASIS: usize = 7;

/// The basis at one (l, v) in the local frame ($n = z$): lit side only for the lobes.
/// Times the cosine the lobes fit Blinn-Phong shading, a physical lobe (lit side only,
/// falling to zero at the terminator) rather than a free bump, so the light that explains
/// the painting best is the one the shading's falloff points to, and flat tones read
/// through it come out smoother (measured: docs/notes/history.md, "Source comments").
pub fn basis(l: DVec3, v: DVec3) -> [f64; BASIS] {
    let nl = l.z.max(0.0);
    let nh = if nl > 0.0 { (l + v).normalize_or(DVec3::Z).z.max(0.0) } else { 0.0 };
    let e4 = nh * nh * nh * nh;
    let e16 = e4 * e4 * e4 * e4;
    let e64 = e16 * e16 * e16 * e16;
    [1.0, nl, l.z.min(0.0), e4 * nl, e16 * nl, e64 * nl, e64 * e64 * e64 * e64 * nl]
}

/// Weighted least squares: the coefficients minimizing $\sum_i w_i^2 (b_i \cdot x - y_i)^2$
/// over `(b, y, w)` triples; `None` when the basis is degenerate on them.
// Index loops: a small dense matrix reads clearest by its indices.
#[allow(clippy::needless_range_loop)]
pub fn fit<const N: usize>(points: impl Iterator<Item = ([f64; N], f64, f64)>) -> Option<[f64; N]> {
    let mut a = [[0.0f64; N]; N];
    let mut r = [0.0f64; N];
    for (b, y, w) in points {
        let b = b.map(|x| x * w);
        for i in 0..N {
            for j in i..N {
                a[i][j] += b[i] * b[j];
            }
            r[i] += b[i] * y * w;
        }
    }
    for i in 0..N {
        for j in 0..i {
            a[i][j] = a[j][i];
        }
    }
    solve_small(a, r)
}

/// [`fit`] with the lobes' weights kept non-negative (a lobe subtracted from another makes a
/// highlight with a dark core): the most negative lobe is dropped and the fit repeated.
pub fn fit_plausible(points: &[([f64; BASIS], f64, f64)]) -> Option<[f64; BASIS]> {
    let mut dropped = [false; BASIS];
    loop {
        let x = fit(points.iter().map(|&(b, y, w)| {
            let mut b = b;
            for (v, &d) in b.iter_mut().zip(&dropped) {
                if d {
                    *v = 0.0;
                }
            }
            (b, y, w)
        }))?;
        let worst = (3..BASIS).filter(|&j| !dropped[j] && x[j] < 0.0).min_by(|&i, &j| x[i].total_cmp(&x[j]));
        match worst {
            Some(j) => dropped[j] = true,
            None => return Some(x),
        }
    }
}

/// The proxy's value: $b \cdot x$.
pub fn eval<const N: usize>(b: &[f64; N], x: &[f64; N]) -> f64 {
    b.iter().zip(x).map(|(b, x)| b * x).sum()
}

/// The proxy (any basis of `N` functions, `points[i].0` at pixel i) that best keeps inside
/// intervals `points[i].1` while staying near `start`: it minimizes
///
/// $$ \sum_i w_i^2 \big[ d(b_i \cdot x, I_i)^2 + \mu\,(b_i \cdot x - s_i)^2 \big] $$
///
/// ($d$ the distance to the interval, $\mu$ = [`PULL`]) by active-set Newton steps: the
/// pixels outside their interval pull towards its nearer end, all pixels weakly towards the
/// start. The pull picks, among the proxies that fit every interval, the one nearest a
/// sensible guess. Weights are relative, 1 / (start + 5% of the largest). Returns the
/// coefficients and the values clamped into the intervals.
pub fn fit_within<const N: usize>(points: &[([f64; N], [f64; 2])], start: &[f64]) -> Option<([f64; N], Vec<f64>)> {
    const STEPS: usize = 30;
    let peak = start.iter().copied().fold(0.0, f64::max);
    if peak <= 0.0 {
        return None;
    }
    let floor = 0.05 * peak;
    let w: Vec<f64> = start.iter().map(|&s| 1.0 / (s + floor)).collect();
    let sq = PULL.sqrt();
    let mut x = fit(points.iter().zip(start).zip(&w).map(|((&(b, _), &s), &w)| (b, s, w)))?;
    let mut active: Vec<i8> = vec![0; points.len()];
    for _ in 0..STEPS {
        let mut changed = false;
        for (a, &(b, [lo, hi])) in active.iter_mut().zip(points) {
            let f = eval(&b, &x);
            let next = if f < lo { -1 } else if f > hi { 1 } else { 0 };
            changed |= next != *a;
            *a = next;
        }
        if !changed {
            break;
        }
        let rows = points.iter().zip(start).zip(&w).zip(&active).flat_map(|((((b, [lo, hi]), &s), &w), &a)| {
            let bound = match a {
                -1 => Some((*b, *lo, w)),
                1 => Some((*b, *hi, w)),
                _ => None,
            };
            std::iter::once((*b, s, w * sq)).chain(bound)
        });
        x = fit(rows)?;
    }
    let t = points.iter().map(|&(b, [lo, hi])| eval(&b, &x).clamp(lo, hi)).collect();
    Some((x, t))
}

/// How strongly [`fit_within`] keeps to its start, against the intervals.
pub const PULL: f64 = 0.001;

/// Solves a small dense system by Gaussian elimination with partial pivoting (and a tiny
/// ridge, so an unused basis function does not make it singular).
#[allow(clippy::needless_range_loop)]
fn solve_small<const N: usize>(mut a: [[f64; N]; N], mut r: [f64; N]) -> Option<[f64; N]> {
    let scale = (0..N).map(|i| a[i][i]).fold(0.0, f64::max).max(1e-300);
    for (i, row) in a.iter_mut().enumerate() {
        row[i] += 1e-9 * scale;
    }
    for c in 0..N {
        let p = (c..N).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, p);
        r.swap(c, p);
        for i in c + 1..N {
            let f = a[i][c] / a[c][c];
            for j in c..N {
                a[i][j] -= f * a[c][j];
            }
            r[i] -= f * r[c];
        }
    }
    let mut x = [0.0; N];
    for i in (0..N).rev() {
        x[i] = (r[i] - (i + 1..N).map(|j| a[i][j] * x[j]).sum::<f64>()) / a[i][i];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lambertian_painting_is_its_own_proxy() {
        // S = 0.1 + 0.7 max(n.l, 0) + 0.2 (n.h)^16 over a spread of directions: recovered.
        let truth = [0.1, 0.7, 0.0, 0.0, 0.2, 0.0, 0.0];
        let mut pts = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                let l = DVec3::new(i as f64 / 10.0 - 1.0, j as f64 / 20.0 - 0.5, 0.6).normalize();
                let v = DVec3::new(0.2, j as f64 / 10.0 - 1.0, 0.9).normalize();
                let b = basis(l, v);
                pts.push((b, eval(&b, &truth), 1.0));
            }
        }
        let x = fit(pts.into_iter()).expect("a well-posed fit");
        for (a, b) in x.iter().zip(truth) {
            assert!((a - b).abs() < 1e-6, "{x:?}");
        }
    }
}
