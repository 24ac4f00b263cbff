//! A block solver for products with one large sparse table beside small dense ones: the
//! four-factor product p(l) q(h) r(v) s(u, v) of thesis 4.2.1, whose uv table has most of
//! the unknowns.
//!
//! With the unknowns split into the small factors (index set 1) and the large one (2),
//!
//! $$ \mathbf G = \begin{pmatrix} \mathbf G_{11} & \mathbf G_{12} \\ \mathbf G_{21} &
//! \mathbf G_{22} \end{pmatrix}, \quad \mathbf S = \mathbf G_{11} - \mathbf G_{12}
//! \mathbf G_{22}^{-1} \mathbf G_{21}, $$
//!
//! the solve is $\mathbf t = \mathbf G_{22}^{-1} \mathbf b_2$,
//! $\mathbf y_1 = \mathbf S^{-1}(\mathbf b_1 - \mathbf G_{12} \mathbf t)$,
//! $\mathbf y_2 = \mathbf t - \mathbf X \mathbf y_1$ with $\mathbf X = \mathbf G_{22}^{-1}
//! \mathbf G_{21}$ precomputed. $\mathbf G_{22}$ is a grid-like sparse matrix whose
//! Cholesky factor stays small; the small factors couple to everything, and a general sparse
//! ordering pays for that coupling on every solve, while here it is one dense product.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Accum, Mat, Par, Side};

use super::sparse::SparseLlt;

use super::system::SymCsc;
use crate::error::{Error, Result};

/// The largest dense part (set 1) this solver takes: $\mathbf S^{-1}$ is n₁².
pub const MAX_DENSE: usize = 1024;
/// The largest sparse part (set 2): $\mathbf X$ is n₂ × n₁.
pub const MAX_SPARSE: usize = 16384;

pub(crate) struct Schur {
    /// Global indices of the dense and sparse parts.
    dense: Vec<usize>,
    sparse: Vec<usize>,
    /// Cholesky factor of $\mathbf G_{22}$.
    g22: SparseLlt,
    /// $\mathbf G_{12}$ by columns of set 2: (row in set 1, value).
    g12: Vec<Vec<(u32, f64)>>,
    /// $\mathbf X = \mathbf G_{22}^{-1} \mathbf G_{21}$, n₂ × n₁.
    x: Mat<f64>,
    /// $\mathbf S^{-1}$, n₁ × n₁.
    s_inv: Mat<f64>,
}

impl Schur {
    /// Factor `g` with `sparse` (sorted global indices) as set 2.
    pub fn new(g: &SymCsc, sparse: Vec<usize>, not_spd: fn(&str) -> Error) -> Result<Schur> {
        let n = g.n;
        // Position of each global index in its set: set 1 as-is, set 2 with the high bit.
        let mut slot = vec![usize::MAX; n];
        for (k, &i) in sparse.iter().enumerate() {
            slot[i] = usize::MAX / 2 + k;
        }
        let mut dense = Vec::new();
        for (i, s) in slot.iter_mut().enumerate() {
            if *s == usize::MAX {
                *s = dense.len();
                dense.push(i);
            }
        }
        let (n1, n2) = (dense.len(), sparse.len());
        let in2 = |s: usize| s >= usize::MAX / 2;
        let mut g11 = Mat::<f64>::zeros(n1, n1);
        let mut g21 = Mat::<f64>::zeros(n2, n1);
        let mut g12 = vec![Vec::new(); n2];
        let (mut col_ptr, mut rows, mut vals) = (vec![0usize], Vec::new(), Vec::new());
        // Columns of G in set-2 order, so G22 comes out in compressed-column form.
        let order: Vec<usize> = dense.iter().chain(&sparse).copied().collect();
        for &c in &order {
            let sc = slot[c];
            for k in g.col_ptr[c]..g.col_ptr[c + 1] {
                let (sr, v) = (slot[g.row[k]], g.val[k]);
                match (in2(sr), in2(sc)) {
                    (false, false) => g11[(sr, sc)] = v,
                    (true, false) => g21[(sr - usize::MAX / 2, sc)] = v,
                    (false, true) => g12[sc - usize::MAX / 2].push((sr as u32, v)),
                    (true, true) => {
                        rows.push(sr - usize::MAX / 2);
                        vals.push(v);
                    }
                }
            }
            if in2(sc) {
                col_ptr.push(rows.len());
            }
        }
        // G's columns list rows in ascending global order, and set 2 is sorted, so the rows
        // of each G22 column are ascending too.
        let llt = SparseLlt::new(n2, col_ptr, rows, vals).map_err(|e| e.unwrap_or_else(|| not_spd("sparse block")))?;
        let mut x = g21.clone();
        llt.solve_in_place(&mut x);
        let mut s = g11;
        faer::linalg::matmul::matmul(&mut s, Accum::Add, g21.transpose(), &x, -1.0, Par::rayon(0));
        let s_inv = s.llt(Side::Lower).map_err(|_| not_spd("Schur complement"))?.inverse();
        Ok(Schur { dense, sparse, g22: llt, g12, x, s_inv })
    }

    /// $\mathbf y = \mathbf G^{-1} \mathbf b$ for an n × 3 right-hand side.
    pub fn solve(&self, b: &Mat<f64>) -> Mat<f64> {
        let (n1, n2) = (self.dense.len(), self.sparse.len());
        let mut t = Mat::from_fn(n2, 3, |r, c| b[(self.sparse[r], c)]);
        let mut r1 = Mat::from_fn(n1, 3, |r, c| b[(self.dense[r], c)]);
        self.g22.solve_in_place(&mut t);
        for (j, col) in self.g12.iter().enumerate() {
            let tj = [t[(j, 0)], t[(j, 1)], t[(j, 2)]];
            for &(i, v) in col {
                for c in 0..3 {
                    r1[(i as usize, c)] -= v * tj[c];
                }
            }
        }
        let mut y1 = Mat::zeros(n1, 3);
        faer::linalg::matmul::matmul(&mut y1, Accum::Replace, &self.s_inv, &r1, 1.0, Par::Seq);
        faer::linalg::matmul::matmul(&mut t, Accum::Add, &self.x, &y1, -1.0, Par::Seq);
        let mut y = Mat::zeros(n1 + n2, 3);
        for c in 0..3 {
            for (r, &i) in self.dense.iter().enumerate() {
                y[(i, c)] = y1[(r, c)];
            }
            for (r, &i) in self.sparse.iter().enumerate() {
                y[(i, c)] = t[(r, c)];
            }
        }
        y
    }
}
