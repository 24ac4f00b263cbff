//! Lookup tables and their interpolation.
//!
//! A table of resolution $M$ has $M$ nodes per axis at coordinates $t_i = i / (M - 1)$,
//! endpoints included. A coordinate between nodes is linearly (1D) or bilinearly (2D)
//! interpolated, which is exactly what a GPU does with a `GL_LINEAR` texture of $M$ texels
//! sampled at $(t (M - 1) + 0.5) / M$. Each sample therefore touches 2 (1D) or 4 (2D) table
//! entries: one row of the matrix $\mathbf{A}_j$ in eq. 3.3.

/// Up to four (index, weight) pairs: the interpolation stencil of one lookup.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stencil {
    pub index: [u32; 4],
    pub weight: [f64; 4],
    pub len: u8,
}

impl Stencil {
    /// The (index, weight) pairs.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..self.len as usize).map(|k| (self.index[k] as usize, self.weight[k]))
    }
}

/// Node index and fraction of a coordinate $t \in [0, 1]$ on $M$ nodes. The last cell is
/// closed, so $t = 1$ lands on node $M - 1$ with weight 1.
fn cell(t: f64, m: usize) -> (usize, f64) {
    let x = t.clamp(0.0, 1.0) * (m - 1) as f64;
    // x ≥ 0 (or NaN, which `as` sends to 0), so truncation is the floor, without a libm call.
    let i = (x as usize).min(m - 2);
    (i, x - i as f64)
}

/// Linear interpolation stencil on a 1D table of `m` ≥ 2 nodes.
pub fn stencil_1d(t: f64, m: usize) -> Stencil {
    let (i, f) = cell(t, m);
    Stencil { index: [i as u32, i as u32 + 1, 0, 0], weight: [1.0 - f, f, 0.0, 0.0], len: 2 }
}

/// Bilinear stencil on an `m` × `m` table stored row by row (index = y·m + x).
pub fn stencil_2d(t: [f64; 2], m: usize) -> Stencil {
    let (i, fx) = cell(t[0], m);
    let (j, fy) = cell(t[1], m);
    let at = |x: usize, y: usize| (y * m + x) as u32;
    Stencil {
        index: [at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)],
        weight: [(1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy],
        len: 4,
    }
}

/// Rows of a finite-difference operator over one table: each row is a list of
/// (node index, coefficient). Used for the Laplacian (eq. 3.4's $\mathbf{L}_j$) and for the
/// first-difference damping.
pub type Rows = Vec<Vec<(usize, f64)>>;

/// Second-difference (Laplacian) rows of a table with `m` nodes per axis in `dim` dimensions,
/// in units of the table coordinate: $(y_{i-1} - 2 y_i + y_{i+1}) / h^2$ with $h = 1/(M-1)$.
///
/// **Boundaries.** A row is emitted only where its stencil fits inside the table: interior
/// nodes get the full 3-point (1D) or 5-point (2D) stencil, edge nodes of a 2D table get the
/// 1D second difference along their edge, corners get none. No boundary value is imposed, so
/// where the data is silent the table continues linearly (the natural boundary condition of
/// a thin plate), rather than being pulled toward zero.
pub fn laplacian(m: usize, dim: usize) -> Rows {
    let h = 1.0 / (m - 1) as f64;
    let s = 1.0 / (h * h);
    let mut rows = Vec::new();
    if dim == 1 {
        for i in 1..m - 1 {
            rows.push(vec![(i - 1, s), (i, -2.0 * s), (i + 1, s)]);
        }
        return rows;
    }
    let at = |x: usize, y: usize| y * m + x;
    for y in 0..m {
        for x in 0..m {
            let interior_x = x > 0 && x < m - 1;
            let interior_y = y > 0 && y < m - 1;
            let mut row = Vec::with_capacity(5);
            let mut centre = 0.0;
            if interior_x {
                row.push((at(x - 1, y), s));
                row.push((at(x + 1, y), s));
                centre -= 2.0 * s;
            }
            if interior_y {
                row.push((at(x, y - 1), s));
                row.push((at(x, y + 1), s));
                centre -= 2.0 * s;
            }
            if !row.is_empty() {
                row.push((at(x, y), centre));
                rows.push(row);
            }
        }
    }
    rows
}

/// First-difference rows $(y_{i+1} - y_i)/h$ along each axis: penalizing them pulls a table
/// toward a constant where the data leaves it free.
pub fn gradient(m: usize, dim: usize) -> Rows {
    let s = (m - 1) as f64;
    let mut rows = Vec::new();
    if dim == 1 {
        for i in 0..m - 1 {
            rows.push(vec![(i, -s), (i + 1, s)]);
        }
        return rows;
    }
    for y in 0..m {
        for x in 0..m {
            if x + 1 < m {
                rows.push(vec![(y * m + x, -s), (y * m + x + 1, s)]);
            }
            if y + 1 < m {
                rows.push(vec![(y * m + x, -s), ((y + 1) * m + x, s)]);
            }
        }
    }
    rows
}

/// Evaluate a 1D table (linear interpolation) at coordinate `t`.
pub fn lookup_1d<const C: usize>(table: &[[f64; C]], t: f64) -> [f64; C] {
    let s = stencil_1d(t, table.len());
    combine(table, &s)
}

/// Evaluate an `m` × `m` table (bilinear) at coordinate `t`.
pub fn lookup_2d<const C: usize>(table: &[[f64; C]], m: usize, t: [f64; 2]) -> [f64; C] {
    combine(table, &stencil_2d(t, m))
}

fn combine<const C: usize>(table: &[[f64; C]], s: &Stencil) -> [f64; C] {
    let mut out = [0.0; C];
    for (i, w) in s.iter() {
        for c in 0..C {
            out[c] += w * table[i][c];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stencil_weights_sum_to_one_and_interpolate_linear_functions() {
        let m = 7;
        let table: Vec<[f64; 1]> = (0..m).map(|i| [3.0 * i as f64 / (m - 1) as f64 + 1.0]).collect();
        for k in 0..=50 {
            let t = k as f64 / 50.0;
            let s = stencil_1d(t, m);
            assert!((s.weight.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            let v = lookup_1d(&table, t)[0];
            assert!((v - (3.0 * t + 1.0)).abs() < 1e-12, "t {t}: {v}");
        }
    }

    #[test]
    fn bilinear_reproduces_bilinear_functions() {
        let m = 5;
        let f = |x: f64, y: f64| 2.0 + x - 3.0 * y + 4.0 * x * y;
        let table: Vec<[f64; 1]> = (0..m * m)
            .map(|k| [f((k % m) as f64 / (m - 1) as f64, (k / m) as f64 / (m - 1) as f64)])
            .collect();
        for (x, y) in [(0.0, 0.0), (1.0, 1.0), (0.33, 0.71), (0.5, 0.999), (1.0, 0.2)] {
            let v = lookup_2d(&table, m, [x, y])[0];
            assert!((v - f(x, y)).abs() < 1e-12, "({x}, {y}): {v} vs {}", f(x, y));
        }
    }

    #[test]
    fn laplacian_vanishes_on_linear_tables_and_not_on_quadratics() {
        for dim in [1, 2] {
            let m = 6;
            let n = if dim == 1 { m } else { m * m };
            let coord = |k: usize| ((k % m) as f64, (k / m) as f64);
            let linear: Vec<f64> = (0..n).map(|k| 1.0 + 2.0 * coord(k).0 - coord(k).1).collect();
            let quad: Vec<f64> = (0..n).map(|k| coord(k).0 * coord(k).0).collect();
            let apply = |y: &[f64]| -> f64 {
                laplacian(m, dim).iter().map(|r| r.iter().map(|&(i, c)| c * y[i]).sum::<f64>().abs()).sum()
            };
            assert!(apply(&linear) < 1e-9, "dim {dim}");
            assert!(apply(&quad) > 1.0, "dim {dim}");
        }
    }
}
