//! Sparse Cholesky of the normal matrix through faer's low-level interface, which lets a
//! solve run single-threaded. The high-level `Llt::solve_in_place` follows faer's global
//! parallelism, and forking threads per supernode made a three-column solve 3–4× slower
//! than doing it on one core (1.35 ms against 0.43 ms for 3072 unknowns, measured here).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering};
use faer::perm::PermRef;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Mat, Par, Side};

use crate::error::{Error, Result};

/// The order in which the factorization eliminates the unknowns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Order {
    /// Approximate minimum degree (AMD): the fill-reducing order for any pattern.
    Amd,
    /// Ascending degree, for a G of products of 1D tables more than [`FULL_SHARE`] full
    /// (AMD otherwise). Every sample couples one node of each table, and the nodes most
    /// samples meet couple to most of the others: eliminating the least coupled first is
    /// minimum degree without the updates, which there fills 5–10% more than AMD, whose
    /// updates cost more than that fill (BENCHMARKS.md: a quarter of the symbolic analysis).
    /// In a grid the fill comes from the elimination itself, which only the updates see
    /// (twice AMD's in a four-factor product).
    Degree,
}

/// Share of G's entries beyond which [`Order::Degree`] applies (products of 1D tables are
/// 11–21% full; sparser, AMD is cheap and its order worth more).
const FULL_SHARE: f64 = 0.1;
/// ...up to this many unknowns, where even a dense factor (n³/3 ≤ 1.2 Gflop) is a fraction
/// of a second, whatever the order.
const DEGREE_MAX: usize = 1536;

/// Factors with at least this many nonzeros are computed on every thread.
const PARALLEL_FACTOR: usize = 200_000;
/// Factors with more nonzeros than this split a few-column solve between two threads.
const SPLIT_FROM: usize = 2_000_000;

/// $\mathbf L \mathbf L^\top$ of a symmetric positive definite sparse matrix.
pub(crate) struct SparseLlt {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
}

impl SparseLlt {
    /// Factor the matrix given in full compressed columns (rows ascending in each column),
    /// eliminating in `order`. `Err(None)` means it is not positive definite.
    pub fn new(n: usize, col_ptr: Vec<usize>, row: Vec<usize>, val: Vec<f64>, order: Order) -> Result<SparseLlt, Option<Error>> {
        let by_degree = (order == Order::Degree && n <= DEGREE_MAX && row.len() as f64 > FULL_SHARE * (n * n) as f64).then(|| degree_order(&col_ptr));
        let ordering = match &by_degree {
            Some((fwd, inv)) => SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n)),
            None => SymmetricOrdering::Amd,
        };
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row);
        let mat = SparseColMat::new(symbolic, val);
        let sym = factorize_symbolic_cholesky(mat.symbolic(), Side::Lower, ordering, Default::default())
            .map_err(|e| Some(Error::Numeric(format!("symbolic factorization failed: {e:?}"))))?;
        let mut values = vec![0.0; sym.len_val()];
        // The numeric factorization is the heavy part: threads pay off there, once the factor
        // is large enough to outweigh forking them (below, one core is faster).
        let par = if sym.len_val() >= PARALLEL_FACTOR { Par::rayon(0) } else { Par::Seq };
        let scratch = sym.factorize_numeric_llt_scratch::<f64>(par, Default::default());
        let mut mem = MemBuffer::try_new(scratch).map_err(|_| Some(Error::Numeric("out of memory".into())))?;
        sym.factorize_numeric_llt::<f64>(
            &mut values,
            mat.as_ref(),
            Side::Lower,
            Default::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|_| None)?;
        Ok(SparseLlt { symbolic: sym, values })
    }

    /// Solve in place for the columns of `rhs`: on the calling thread for a few columns
    /// (a refit), with threads for many (while preparing).
    pub fn solve_in_place(&self, rhs: &mut Mat<f64>) {
        // A large factor is read from memory on every solve, and one core does not draw all
        // of the memory bandwidth: the columns are split between two threads, each solving
        // on its own (faer's own threads fork per supernode, which costs more than it wins).
        if rhs.ncols() >= 2 && rhs.ncols() <= 8 && self.values.len() > SPLIT_FROM && rayon::current_num_threads() > 1 {
            let half = rhs.ncols().div_ceil(2);
            let (a, b) = rhs.as_mut().split_at_col_mut(half);
            rayon::join(|| self.solve_seq(a), || self.solve_seq(b));
            return;
        }
        let par = if rhs.ncols() > 8 { Par::rayon(0) } else { Par::Seq };
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par));
        LltRef::<usize, f64>::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            par,
            MemStack::new(&mut mem),
        );
    }
}

/// The permutation (forward, inverse) that takes columns in ascending order of their
/// nonzeros, ties in their own order.
fn degree_order(col_ptr: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let n = col_ptr.len() - 1;
    let mut fwd: Vec<usize> = (0..n).collect();
    fwd.sort_by_key(|&c| col_ptr[c + 1] - col_ptr[c]);
    let mut inv = vec![0; n];
    for (i, &c) in fwd.iter().enumerate() {
        inv[c] = i;
    }
    (fwd, inv)
}

impl SparseLlt {
    /// Solve in place on the calling thread.
    fn solve_seq(&self, rhs: faer::MatMut<'_, f64>) {
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), Par::Seq));
        LltRef::<usize, f64>::new(&self.symbolic, &self.values).solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut mem));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric positive definite matrix a fifth full (taking the degree order): random
    /// symmetric entries where a hash says so, each column's diagonal its absolute row sum + 1.
    fn fifth_full(n: usize) -> (Vec<usize>, Vec<usize>, Vec<f64>, Mat<f64>) {
        let hash = |i: usize, j: usize| ((i.min(j) * 7919 + i.max(j) * 104_729) % 1009) as f64 / 1009.0;
        let mut dense = Mat::<f64>::zeros(n, n);
        for i in 0..n {
            for j in 0..i {
                // Denser where both nodes are low: the degrees differ, as a product's do.
                if hash(i, j) < 0.4 * (1.0 - (i + j) as f64 / (2 * n) as f64) {
                    let x = hash(j, i + n) - 0.5;
                    dense[(i, j)] = x;
                    dense[(j, i)] = x;
                }
            }
        }
        for i in 0..n {
            dense[(i, i)] = (0..n).map(|j| dense[(i, j)].abs()).sum::<f64>() + 1.0;
        }
        let (mut col_ptr, mut row, mut val) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if dense[(i, j)] != 0.0 {
                    row.push(i);
                    val.push(dense[(i, j)]);
                }
            }
            col_ptr.push(row.len());
        }
        (col_ptr, row, val, dense)
    }

    #[test]
    fn a_near_full_matrix_ordered_by_degree_solves_exactly() {
        let n = 300;
        let (col_ptr, row, val, dense) = fifth_full(n);
        assert!(row.len() as f64 > FULL_SHARE * (n * n) as f64, "{} of {}", row.len(), n * n);
        let (fwd, inv) = degree_order(&col_ptr);
        assert!(fwd.windows(2).all(|w| col_ptr[w[0] + 1] - col_ptr[w[0]] <= col_ptr[w[1] + 1] - col_ptr[w[1]]));
        assert!((0..n).all(|i| fwd[inv[i]] == i));
        let llt = SparseLlt::new(n, col_ptr, row, val, Order::Degree).map_err(|_| "not factored").unwrap();
        let b = Mat::<f64>::from_fn(n, 3, |i, c| ((i * 31 + c * 17) % 23) as f64 - 11.0);
        let mut x = b.clone();
        llt.solve_in_place(&mut x);
        let residual = &dense * &x - &b;
        let worst = (0..n).flat_map(|i| (0..3).map(move |c| (i, c))).map(|(i, c)| residual[(i, c)].abs()).fold(0.0, f64::max);
        assert!(worst < 1e-10, "largest residual {worst:e}");
    }
}
