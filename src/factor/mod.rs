//! Factorization.
