//! Prepared systems on disk, so a standard scene is prepared once, ever (thesis 3.2.2: the
//! pseudo-inverse "can be precomputed" for a fixed sampling pattern).
//!
//! A file is keyed by the pattern's and the settings' fingerprints and this format's
//! version. It holds the factored solver only; the sample matrix is rebuilt from the pattern,
//! which is cheap. A sparse Cholesky factor is stored as its normal matrix and refactored on
//! load (faer's factor is not serializable), which still skips the assembly.
//!
//! Layout, little endian: magic `BRDFPREP`, `u32` version, `u64` key, `u64` payload length,
//! payload, and the SHA-256 of everything before it. A file whose magic, version, key,
//! length or hash disagrees, whose sizes do not fit the system, or that holds a value that
//! is not finite, is stale or corrupt: it is rebuilt and overwritten, never trusted.
//!
//! The hash is cryptographic so that no accidental or crafted change (version 1 used
//! FNV-1a, which a crafted file can match) passes as intact; every number is checked finite
//! as it is read, so a file cannot bring a NaN into a solve. (Whoever can write the cache
//! directory can still write a consistent file with a wrong system: the directory is the
//! user's own.)

use std::path::PathBuf;
use std::time::Instant;

use faer::Mat;

use super::prepared::{factor, Prepared, Solver, Spectral};
use super::system::{Design, SymCsc};
use super::{Channels, Input, Pattern, Settings};
use crate::error::{Error, Result};
use crate::util::Fnv;
use sha2::{Digest, Sha256};

const MAGIC: &[u8; 8] = b"BRDFPREP";
/// 2: SHA-256 instead of FNV-1a, values checked finite. 3: above 128 unknowns the
/// factor is sparse (an older file's dense inverse would solve, but slower).
const VERSION: u32 = 3;
/// Bytes of the hash at the end of a file.
const HASH: usize = 32;
/// Bytes before the payload: magic, version, key, length.
const HEADER: usize = 8 + 4 + 8 + 8;

/// What the cache did.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Loaded from disk.
    Hit,
    /// Not on disk: prepared and stored.
    Miss,
    /// On disk but unusable (the reason): prepared again and overwritten.
    Rebuilt(String),
    /// Not cacheable (custom projections), or the cache could not be written (the reason).
    Uncached(String),
}

/// A directory of prepared systems.
#[derive(Clone, Debug)]
pub struct Cache {
    dir: PathBuf,
}

impl Cache {
    pub fn new(dir: impl Into<PathBuf>) -> Cache {
        Cache { dir: dir.into() }
    }

    /// `$BRDFPAINT_CACHE`, else `$XDG_CACHE_HOME/brdfpaint`, else `~/.cache/brdfpaint`.
    pub fn user() -> Option<Cache> {
        let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty()).map(PathBuf::from);
        var("BRDFPAINT_CACHE")
            .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("brdfpaint")))
            .or_else(|| var("HOME").map(|d| d.join(".cache").join("brdfpaint")))
            .map(Cache::new)
    }

    /// The file a pattern and settings are stored in.
    pub fn path(&self, pattern: &Pattern, settings: &Settings) -> PathBuf {
        self.dir.join(format!("{:016x}.prep", key(pattern, settings)))
    }

    /// Load the prepared system for a pattern and settings, or prepare and store it.
    pub fn prepare(&self, pattern: &Pattern, settings: &Settings) -> Result<(Prepared, Outcome)> {
        if settings.channels == Channels::Coupled {
            // Two systems, each its own file: the luminance's is the independent fit's.
            let (luminance, first) = self.prepare(pattern, &settings.luminance())?;
            let mut outcome = first;
            let mut chroma = Vec::new();
            for part in settings.chroma() {
                let (system, then) = self.prepare(pattern, &part)?;
                if outcome == Outcome::Hit {
                    outcome = then;
                }
                chroma.push(system);
            }
            return Ok((Prepared::couple(settings, luminance, chroma), outcome));
        }
        if settings.factors.iter().any(|f| matches!(f.input, Input::Custom(_))) {
            let p = super::prepare(pattern, settings)?;
            return Ok((p, Outcome::Uncached("custom projections are not cacheable".into())));
        }
        let path = self.path(pattern, settings);
        let k = key(pattern, settings);
        let unknowns = settings.factors.iter().map(|f| f.len()).sum();
        let stale = match crate::fsio::read_regular(&path, max_file_bytes(unknowns)) {
            Ok(bytes) => match load(&bytes, k, pattern, settings) {
                Ok(p) => return Ok((p, Outcome::Hit)),
                Err(reason) => Some(reason),
            },
            Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => Some(unreadable(e)),
        };
        let prepared = super::prepare(pattern, settings)?;
        let written = std::fs::create_dir_all(&self.dir)
            .map_err(|e| Error::io(&self.dir, e))
            .and_then(|()| crate::commit::write_atomic(&path, &store(&prepared, k)));
        let outcome = match (written, stale) {
            (Err(e), _) => Outcome::Uncached(e.to_string()),
            (Ok(()), Some(reason)) => Outcome::Rebuilt(reason),
            (Ok(()), None) => Outcome::Miss,
        };
        Ok((prepared, outcome))
    }
}

/// The largest file [`store`] writes for a system of `n` unknowns: a sparse normal matrix
/// of at most n² entries (index and value, 16 bytes each) is the largest payload, above a
/// dense n × n inverse or a spectral basis. A file beyond it is refused before it is read.
fn max_file_bytes(n: usize) -> u64 {
    let n = n as u64;
    let payload = 16u64.saturating_mul(n).saturating_mul(n).saturating_add(24 * (n + 1)).saturating_add(48);
    payload.saturating_add((HEADER + HASH) as u64)
}

/// Why an existing cache file could not be read (a FIFO, a device, too large): the reason
/// without the path, which the caller names.
fn unreadable(e: Error) -> String {
    match e {
        Error::Format { reason, .. } => reason,
        Error::Io { source, .. } => source.to_string(),
        other => other.to_string(),
    }
}

fn key(pattern: &Pattern, settings: &Settings) -> u64 {
    let mut h = Fnv::new();
    h.write(MAGIC);
    h.write(&VERSION.to_le_bytes());
    h.write(env!("CARGO_PKG_VERSION").as_bytes());
    h.write(&pattern.fingerprint().to_le_bytes());
    h.write(&settings.fingerprint().to_le_bytes());
    h.finish()
}

fn store(prepared: &Prepared, key: u64) -> Vec<u8> {
    let (_, _, solver) = prepared.parts();
    let mut p = Writer::default();
    p.f64(prepared.prepare_s);
    match solver {
        Solver::Dense(inv) => {
            p.u64(0);
            p.mat(inv);
        }
        Solver::Sparse(_, g) => {
            p.u64(1);
            p.u64(g.n as u64);
            p.u64(g.row.len() as u64);
            g.col_ptr.iter().for_each(|&x| p.u64(x as u64));
            g.row.iter().for_each(|&x| p.u64(x as u64));
            g.val.iter().for_each(|&x| p.f64(x));
        }
        Solver::Spectral(s) => {
            p.u64(2);
            p.mat(&s.basis);
            s.singular.iter().for_each(|&x| p.f64(x));
            s.weight.iter().for_each(|&x| p.f64(x));
        }
    }
    let payload = p.0;
    let mut out = Vec::with_capacity(HEADER + payload.len() + HASH);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&key.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    let hash = Sha256::digest(&out);
    out.extend_from_slice(&hash);
    out
}

/// Parse and check a cache file; the error is why it cannot be used.
fn load(bytes: &[u8], key: u64, pattern: &Pattern, settings: &Settings) -> std::result::Result<Prepared, String> {
    let start = Instant::now();
    if bytes.len() < HEADER + HASH || &bytes[..8] != MAGIC {
        return Err("not a prepared-system file".into());
    }
    let mut r = Reader(&bytes[8..]);
    if r.u32()? != VERSION {
        return Err("written by another version".into());
    }
    if r.u64()? != key {
        return Err("key does not match".into());
    }
    let len = usize::try_from(r.u64()?).map_err(|_| "bad length")?;
    if r.0.len() != len.checked_add(HASH).ok_or("bad length")? {
        return Err("truncated or oversized".into());
    }
    let (hashed, hash) = bytes.split_at(bytes.len() - HASH);
    if Sha256::digest(hashed).as_slice() != hash {
        return Err("checksum mismatch".into());
    }
    let payload = &hashed[HEADER..];
    let design = Design::new(pattern, settings).map_err(|e| e.to_string())?;
    let n = design.n;
    let mut r = Reader(payload);
    let _original_prepare_s = r.f64()?;
    let solver = match r.u64()? {
        0 => Solver::Dense(r.mat(n)?),
        1 => {
            let (gn, nnz) = (r.u64()? as usize, r.u64()? as usize);
            if gn != n || nnz > n.saturating_mul(n) {
                return Err("sizes do not fit the system".into());
            }
            let col_ptr = (0..=n).map(|_| r.u64().map(|x| x as usize)).collect::<std::result::Result<Vec<_>, _>>()?;
            let row = (0..nnz).map(|_| r.u64().map(|x| x as usize)).collect::<std::result::Result<Vec<_>, _>>()?;
            let val = (0..nnz).map(|_| r.f64()).collect::<std::result::Result<Vec<_>, _>>()?;
            let sorted = col_ptr.windows(2).all(|w| w[0] <= w[1]) && col_ptr[n] == nnz && row.iter().all(|&i| i < n);
            if !sorted {
                return Err("malformed sparse matrix".into());
            }
            factor(&SymCsc { n, col_ptr, row, val }, settings).map_err(|e| e.to_string())?
        }
        2 => {
            let basis = r.mat(n)?;
            let singular = (0..n).map(|_| r.f64()).collect::<std::result::Result<Vec<_>, _>>()?;
            let weight = (0..n).map(|_| r.f64()).collect::<std::result::Result<Vec<_>, _>>()?;
            Solver::Spectral(Spectral::with_weights(basis, singular, weight))
        }
        _ => return Err("unknown solver".into()),
    };
    if !r.0.is_empty() {
        return Err("trailing data".into());
    }
    Ok(Prepared::from_parts(settings.clone(), design, solver, start.elapsed().as_secs_f64()))
}

#[derive(Default)]
struct Writer(Vec<u8>);

impl Writer {
    fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn f64(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn mat(&mut self, m: &Mat<f64>) {
        self.u64(m.nrows() as u64);
        for c in 0..m.ncols() {
            for r in 0..m.nrows() {
                self.f64(m[(r, c)]);
            }
        }
    }
}

struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> std::result::Result<[u8; N], String> {
        if self.0.len() < N {
            return Err("truncated".into());
        }
        let (a, b) = self.0.split_at(N);
        self.0 = b;
        Ok(a.try_into().expect("split at N"))
    }
    fn u32(&mut self) -> std::result::Result<u32, String> {
        self.take::<4>().map(u32::from_le_bytes)
    }
    fn u64(&mut self) -> std::result::Result<u64, String> {
        self.take::<8>().map(u64::from_le_bytes)
    }
    /// A finite `f64`: a NaN or infinity in a cached system is corruption.
    fn f64(&mut self) -> std::result::Result<f64, String> {
        let x = self.take::<8>().map(f64::from_le_bytes)?;
        if !x.is_finite() {
            return Err("non-finite value".into());
        }
        Ok(x)
    }
    /// A square n × n matrix, column-major, preceded by its size.
    fn mat(&mut self, n: usize) -> std::result::Result<Mat<f64>, String> {
        if self.u64()? as usize != n || self.0.len() < n * n * 8 {
            return Err("matrix size does not fit the system".into());
        }
        let mut m = Mat::zeros(n, n);
        for c in 0..n {
            for r in 0..n {
                m[(r, c)] = self.f64()?;
            }
        }
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::{Analytic, SphereView};
    use crate::factor::{Mapping, Method};
    use glam::DVec3;

    fn case(settings: &Settings) {
        let dir = tempfile::tempdir().unwrap();
        let cache = Cache::new(dir.path().join("c"));
        let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 40).pattern();
        let values = pattern.shade(|q| crate::brdf::Reflectance::shading(&Analytic::suite()[2], q));
        let (fresh, o) = cache.prepare(&pattern, settings).unwrap();
        assert_eq!(o, Outcome::Miss);
        let (cached, o) = cache.prepare(&pattern, settings).unwrap();
        assert_eq!(o, Outcome::Hit);
        assert_eq!(fresh.solver_kind(), cached.solver_kind());
        let (a, b) = (fresh.solve(&values, Mapping::Auto).unwrap(), cached.solve(&values, Mapping::Auto).unwrap());
        assert_eq!(a.tables, b.tables, "a cached system solves exactly as a fresh one");
        // Corrupt one payload byte: the checksum catches it and the file is rebuilt.
        let path = cache.path(&pattern, settings);
        let mut bytes = std::fs::read(&path).unwrap();
        let mid = bytes.len() / 2;
        bytes[mid] ^= 0x40;
        std::fs::write(&path, &bytes).unwrap();
        let (_, o) = cache.prepare(&pattern, settings).unwrap();
        assert_eq!(o, Outcome::Rebuilt("checksum mismatch".into()));
        // Truncated.
        std::fs::write(&path, &bytes[..bytes.len() - 100]).unwrap();
        assert!(matches!(cache.prepare(&pattern, settings).unwrap().1, Outcome::Rebuilt(_)));
        // After a rebuild it is a hit again.
        assert_eq!(cache.prepare(&pattern, settings).unwrap().1, Outcome::Hit);
        // Another pattern is another file.
        let other = SphereView::new(DVec3::new(0.5, 0.5, 1.0), 40).pattern();
        assert_ne!(cache.path(&other, settings), path);
    }

    /// A crafted file: a valid FNV-1a checksum of version 1, or a valid SHA-256, over NaN
    /// entries, is rebuilt, never used.
    #[test]
    fn crafted_files_with_valid_checksums_and_nans_are_rebuilt() {
        let dir = tempfile::tempdir().unwrap();
        let cache = Cache::new(dir.path());
        let settings = Settings::uniform(1, 24).luminance();
        let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 40).pattern();
        assert_eq!(cache.prepare(&pattern, &settings).unwrap().1, Outcome::Miss);
        let path = cache.path(&pattern, &settings);
        let good = std::fs::read(&path).unwrap();
        let mut payload = good[HEADER..good.len() - HASH].to_vec();
        // prepare_s, the solver tag (dense) and the matrix size come first; then entries.
        assert_eq!(u64::from_le_bytes(payload[8..16].try_into().unwrap()), 0, "a dense system");
        for k in 0..4 {
            payload[24 + 8 * k..32 + 8 * k].copy_from_slice(&f64::NAN.to_le_bytes());
        }
        let header = |version: u32| {
            let mut h = good[..HEADER].to_vec();
            h[8..12].copy_from_slice(&version.to_le_bytes());
            h
        };
        // Version 1: FNV-1a of the payload at the end.
        let mut v1 = header(1);
        v1.extend_from_slice(&payload);
        let mut fnv = Fnv::new();
        fnv.write(&payload);
        v1.extend_from_slice(&fnv.finish().to_le_bytes());
        std::fs::write(&path, &v1).unwrap();
        assert_eq!(cache.prepare(&pattern, &settings).unwrap().1, Outcome::Rebuilt("written by another version".into()));
        // Version 2 with a correct SHA-256 of the NaN payload.
        let mut v2 = header(VERSION);
        v2.extend_from_slice(&payload);
        let hash = Sha256::digest(&v2);
        v2.extend_from_slice(&hash);
        std::fs::write(&path, &v2).unwrap();
        assert_eq!(cache.prepare(&pattern, &settings).unwrap().1, Outcome::Rebuilt("non-finite value".into()));
        // A scaled matrix under the old hash: the hash catches it.
        let mut scaled = good.clone();
        let at = HEADER + 24;
        let x = f64::from_le_bytes(scaled[at..at + 8].try_into().unwrap()) * 2.0;
        scaled[at..at + 8].copy_from_slice(&x.to_le_bytes());
        std::fs::write(&path, &scaled).unwrap();
        assert_eq!(cache.prepare(&pattern, &settings).unwrap().1, Outcome::Rebuilt("checksum mismatch".into()));
        assert_eq!(cache.prepare(&pattern, &settings).unwrap().1, Outcome::Hit, "rebuilt, then used");
    }

    /// An entry that is a FIFO, a link to /dev/zero or a file beyond the largest this
    /// system writes is refused before it is read (a FIFO used to hang the fit, /dev/zero
    /// to read until memory ran out), then rebuilt over like a corrupt one.
    #[cfg(unix)]
    #[test]
    fn entries_that_are_not_regular_files_or_too_large_are_rebuilt() {
        let dir = tempfile::tempdir().unwrap();
        let cache = Cache::new(dir.path());
        let settings = Settings::default().luminance();
        let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 40).pattern();
        let path = cache.path(&pattern, &settings);
        let fifo = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
        // SAFETY: a NUL-terminated path that outlives the call.
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
        let outcome = cache.prepare(&pattern, &settings).unwrap().1;
        assert_eq!(outcome, Outcome::Rebuilt("is a FIFO (named pipe); only regular files are read".into()));
        assert!(std::fs::symlink_metadata(&path).unwrap().is_file(), "the FIFO is replaced by the rebuilt file");
        assert_eq!(cache.prepare(&pattern, &settings).unwrap().1, Outcome::Hit);
        std::fs::remove_file(&path).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &path).unwrap();
        let outcome = cache.prepare(&pattern, &settings).unwrap().1;
        assert_eq!(outcome, Outcome::Rebuilt("is a device; only regular files are read".into()));
        let n: usize = settings.factors.iter().map(|f| f.len()).sum();
        std::fs::File::options().write(true).open(&path).unwrap().set_len(max_file_bytes(n) + 1).unwrap();
        let Outcome::Rebuilt(why) = cache.prepare(&pattern, &settings).unwrap().1 else { panic!("not rebuilt") };
        assert!(why.starts_with("larger than the"), "{why}");
        assert_eq!(cache.prepare(&pattern, &settings).unwrap().1, Outcome::Hit);
    }

    #[test]
    fn dense_systems_round_trip_and_corruption_is_rebuilt() {
        let s = Settings::uniform(1, 24).luminance();
        assert_eq!(kind(&s), "dense", "this case must exercise the dense path");
        case(&s);
    }

    /// The solver a settings choose on the standard test pattern.
    fn kind(s: &Settings) -> &'static str {
        let pattern = SphereView::new(DVec3::Z, 40).pattern();
        crate::factor::prepare(&pattern, s).unwrap().solver_kind()
    }

    #[test]
    fn sparse_systems_round_trip_and_corruption_is_rebuilt() {
        let s = Settings::uniform(2, 32).luminance();
        assert_eq!(kind(&s), "sparse", "this case must exercise the sparse path");
        case(&s);
    }

    #[test]
    fn spectral_systems_round_trip() {
        case(&Settings { method: Method::DampedSvd { alpha: 1e-3 }, ..Settings::uniform(1, 24).luminance() });
    }
}
