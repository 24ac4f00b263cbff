//! Prepared-system cache.
