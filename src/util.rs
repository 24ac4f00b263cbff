//! Small helpers shared by several modules: a stable hash for cache keys and file
//! fingerprints, whether to draw progress bars, and the AVX state after a solve.
//! (Whole-or-nothing outputs live in [`crate::commit`], the file-access policy in
//! [`crate::fsio`].)

/// FNV-1a, 64 bit: a stable hash for cache keys and checksums (std's hasher is not stable
/// across releases, and these values are stored in files).
#[derive(Clone, Copy, Debug)]
pub struct Fnv(u64);

impl Fnv {
    pub fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl Default for Fnv {
    fn default() -> Self {
        Self::new()
    }
}

/// Whether progress bars should be drawn: only when stderr is a terminal.
pub fn progress_enabled() -> bool {
    use std::io::IsTerminal;
    std::io::stderr().is_terminal()
}

/// Clear the upper halves of the vector registers.
///
/// faer's AVX-512 matrix kernels return with the upper register state dirty. Until it is
/// cleared, every legacy-SSE instruction that follows pays a transition penalty: measured
/// here, `f64::exp` went from 4 ns to 130 ns per call after one small matrix product,
/// which made a 0.1 ms refit take 0.3 ms. Call this after a faer kernel on a hot path.
#[inline]
pub fn clear_upper_vector_state() {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU supports AVX, checked just above.
        unsafe { zeroupper() }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn zeroupper() {
    std::arch::x86_64::_mm256_zeroupper();
}
