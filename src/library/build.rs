//! The library's fits, in parallel, and its commit.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use glam::DVec3;

use super::{check_output, gallery, index, Entry, Manifest, Picture};
use crate::commit::{Claim, Legacy, StagedDir};
use crate::error::Result;
use crate::factor::cache::Cache;
use crate::factor::Errors;
use crate::litsphere::{self, Outline};
use crate::pipeline::Options;

/// What every picture of a library is fitted with.
pub struct Job<'a> {
    /// The light of every picture (`None`: each one's estimate), the side it is fitted at
    /// and how it is read ([`litsphere::Ask`]; no disk: each one's own).
    pub ask: litsphere::Ask,
    pub opts: &'a Options,
    pub cache: Option<&'a Cache>,
    /// Fits at once (at least 1).
    pub workers: usize,
}

/// A material of the library, with what its index page and its gallery row show.
#[derive(Clone, Debug)]
pub struct Fitted {
    pub name: String,
    pub picture: std::path::PathBuf,
    pub light: DVec3,
    /// The light estimate's spread, degrees (`None`: the light was given).
    pub spread_deg: Option<f64>,
    pub outline: Outline,
    pub errors: Errors,
    pub samples: usize,
    pub notes: Vec<String>,
}

/// A picture that could not be fitted, and the one line that says why.
#[derive(Clone, Debug)]
pub struct Failed {
    pub picture: std::path::PathBuf,
    pub reason: String,
}

/// One picture's outcome, as it happens (for a progress bar).
pub enum Outcome<'a> {
    Fitted(&'a Fitted),
    Failed(&'a Failed),
}

/// What a library run did, in the order of the pictures.
pub struct Report {
    pub fitted: Vec<Fitted>,
    pub failed: Vec<Failed>,
}

/// Fits every picture into `out/NAME/` (as `fit --lit-sphere P --out out/NAME` writes it),
/// the gallery and the index beside them, and commits the library whole. A picture that
/// fails is reported (`tell` hears every outcome as it happens) and the rest go on; with
/// none fitted nothing is written. Errors, one line: `out` is not a library, or writing it
/// failed.
pub fn build(pictures: &[Picture], job: &Job, out: &Path, tell: &(dyn Fn(Outcome) + Sync)) -> Result<Report> {
    check_output(out)?;
    let mut staged = StagedDir::new(out, Claim::new(&[], Legacy::Paths(Default::default())))?;
    staged.keep_inputs(pictures.iter().map(|p| p.path.as_path()));
    let report = fit_all(pictures, job, &staged, tell);
    if report.fitted.is_empty() {
        return Ok(report);
    }
    staged.fill(|dir| write_pages(dir, &report.fitted))?;
    // The folder may have become something else while the pictures were fitted.
    check_output(out)?;
    staged.commit()?;
    Ok(report)
}

/// The gallery, its rows, the index and the manifest of the materials in `dir`.
fn write_pages(dir: &Path, fitted: &[Fitted]) -> Result<()> {
    gallery::write(dir, fitted)?;
    index::write(dir, fitted)?;
    let entries = fitted.iter().map(|f| Entry::new(&f.name, &f.picture, f.light, f.errors)).collect();
    Manifest::new(entries).write(dir)
}

/// Fits the pictures on `job.workers` threads, each into the staged library's `NAME/`.
fn fit_all(pictures: &[Picture], job: &Job, staged: &StagedDir, tell: &(dyn Fn(Outcome) + Sync)) -> Report {
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<std::result::Result<Fitted, Failed>>>> = Mutex::new(vec![None; pictures.len()]);
    // Plain threads, not rayon tasks: a rayon task waiting inside a fit may run another
    // picture's task on its own thread, and each fit makes its GL context current there.
    std::thread::scope(|scope| {
        for _ in 0..job.workers.max(1) {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(picture) = pictures.get(k) else { break };
                let result = fit_one(picture, job, staged).map_err(|e| Failed { picture: picture.path.clone(), reason: e.to_string() });
                match &result {
                    Ok(f) => tell(Outcome::Fitted(f)),
                    Err(f) => tell(Outcome::Failed(f)),
                }
                results.lock().unwrap_or_else(|e| e.into_inner())[k] = Some(result);
            });
        }
    });
    let mut report = Report { fitted: Vec::new(), failed: Vec::new() };
    for result in results.into_inner().unwrap_or_else(|e| e.into_inner()).into_iter().flatten() {
        match result {
            Ok(f) => report.fitted.push(f),
            Err(f) => report.failed.push(f),
        }
    }
    report
}

/// One picture fitted and saved into the staged library's `NAME/` by the path `fit
/// --lit-sphere` takes; the fit itself (its system and samples) is dropped before the next.
fn fit_one(picture: &Picture, job: &Job, staged: &StagedDir) -> Result<Fitted> {
    let lit = litsphere::fit_in(&picture.path, &job.ask, job.opts, job.cache)?;
    staged.fill(|dir| lit.save(&picture.path, &dir.join(&picture.name)))?;
    Ok(Fitted {
        name: picture.name.clone(),
        picture: picture.path.clone(),
        light: lit.light,
        spread_deg: lit.estimate.map(|e| e.spread_deg),
        outline: lit.outline,
        errors: lit.fitted.errors(),
        samples: lit.fitted.samples.len(),
        notes: lit.fitted.notes.iter().map(ToString::to_string).collect(),
    })
}
