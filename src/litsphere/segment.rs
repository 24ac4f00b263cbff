//! Segmentation of a lit-sphere picture: the background's colour, a threshold between it and
//! the sphere, and the connected shapes of a mask.

use crate::images::{neighbours4, Painting};

/// Median colour of the picture's outermost ring of pixels.
pub(super) fn border_median(p: &Painting) -> [f32; 3] {
    let (w, h) = (p.width, p.height);
    let mut ring = Vec::new();
    for i in 0..w {
        ring.push(p.pixels[i]);
        ring.push(p.pixels[(h - 1) * w + i]);
    }
    for j in 0..h {
        ring.push(p.pixels[j * w]);
        ring.push(p.pixels[j * w + w - 1]);
    }
    [0, 1, 2].map(|c| {
        let mut v: Vec<f32> = ring.iter().map(|x| x[c]).collect();
        v.sort_by(f32::total_cmp);
        v[v.len() / 2]
    })
}

/// Largest channel difference after a square root (roughly perceptual: dark rims still
/// differ from a black background).
pub(super) fn perceptual_distance(a: &[f32; 3], b: &[f32; 3]) -> f32 {
    (0..3).map(|c| (a[c].max(0.0).sqrt() - b[c].max(0.0).sqrt()).abs()).fold(0.0, f32::max)
}

/// Otsu's threshold of values in [0, max]: the split with the largest between-class variance.
pub(super) fn otsu(values: &[f32], max: f32) -> f32 {
    const BINS: usize = 256;
    let mut hist = [0usize; BINS];
    for &v in values {
        hist[((v / max * (BINS - 1) as f32) as usize).min(BINS - 1)] += 1;
    }
    let total = values.len() as f64;
    let sum: f64 = hist.iter().enumerate().map(|(i, &n)| i as f64 * n as f64).sum();
    let (mut best, mut best_t, mut w0, mut sum0) = (-1.0, 0usize, 0.0, 0.0);
    for (t, &n) in hist.iter().enumerate() {
        w0 += n as f64;
        sum0 += t as f64 * n as f64;
        let w1 = total - w0;
        if w0 == 0.0 || w1 == 0.0 {
            continue;
        }
        let (m0, m1) = (sum0 / w0, (sum - sum0) / w1);
        let between = w0 * w1 * (m0 - m1).powi(2);
        if between > best {
            best = between;
            best_t = t;
        }
    }
    (best_t as f32 + 0.5) / (BINS - 1) as f32 * max
}

/// 4-connected labels of `mask` (0: background; components numbered from 1).
fn label(mask: &[bool], w: usize, h: usize) -> Vec<u32> {
    let mut labels = vec![0u32; w * h];
    let mut next = 0;
    let mut stack = Vec::new();
    for start in 0..w * h {
        if !mask[start] || labels[start] != 0 {
            continue;
        }
        next += 1;
        labels[start] = next;
        stack.push(start);
        while let Some(k) = stack.pop() {
            for n in neighbours4(k, w, w * h) {
                if mask[n] && labels[n] == 0 {
                    labels[n] = next;
                    stack.push(n);
                }
            }
        }
    }
    labels
}

/// The labels of `mask`'s components ([`label`]) and each one's (label, area).
pub(super) fn components(mask: &[bool], w: usize, h: usize) -> (Vec<u32>, Vec<(u32, usize)>) {
    let labels = label(mask, w, h);
    let n = labels.iter().copied().max().unwrap_or(0) as usize;
    let mut area = vec![0usize; n + 1];
    for &l in &labels {
        area[l as usize] += 1;
    }
    let areas = (1..=n).map(|l| (l as u32, area[l])).collect();
    (labels, areas)
}
