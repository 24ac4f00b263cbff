//! Sparse Cholesky of the normal matrix through faer's low-level interface, which lets a
//! solve run single-threaded. The high-level `Llt::solve_in_place` follows faer's global
//! parallelism, and forking threads per supernode made a three-column solve 3–4× slower
//! than doing it on one core (1.35 ms against 0.43 ms for 3072 unknowns, measured here).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Conj, Mat, Par, Side};

use crate::error::{Error, Result};

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
    /// Factor the matrix given in full compressed columns (rows ascending in each column).
    /// `Err(None)` means it is not positive definite.
    pub fn new(n: usize, col_ptr: Vec<usize>, row: Vec<usize>, val: Vec<f64>) -> Result<SparseLlt, Option<Error>> {
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row);
        let mat = SparseColMat::new(symbolic, val);
        let sym = factorize_symbolic_cholesky(mat.symbolic(), Side::Lower, SymmetricOrdering::Amd, Default::default())
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

impl SparseLlt {
    /// Solve in place on the calling thread.
    fn solve_seq(&self, rhs: faer::MatMut<'_, f64>) {
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), Par::Seq));
        LltRef::<usize, f64>::new(&self.symbolic, &self.values).solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut mem));
    }
}
