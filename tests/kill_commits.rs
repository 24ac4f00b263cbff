//! Whole-or-nothing outputs across a kill at a random moment (issue 13, item 3): `fit`,
//! `sheet`, `render --turntable` and `demo` are started over an earlier output and
//! SIGKILLed at a random time; after the sweep the next run does
//! ([`brdfpaint::commit::sweep_stale`]), the output is the old one or the new one, whole,
//! never a mix; no temporary is left; the user's own files in the directory are kept.
//!
//! Each command is killed [`kills`] times: 20 by default, to keep the suite's time down;
//! `BRDFPAINT_KILLS=100 cargo test --release --test kill_commits` runs the full
//! attack (100 kills per command).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use brdfpaint::commit::{sweep_stale, temporaries};
use brdfpaint::material::Material;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Kills per command: `$BRDFPAINT_KILLS`, else 20 (module docs).
fn kills() -> usize {
    match std::env::var("BRDFPAINT_KILLS") {
        Ok(v) => v.parse().unwrap_or_else(|_| panic!("BRDFPAINT_KILLS={v:?} is not a count")),
        Err(_) => 20,
    }
}

/// When to kill run `k` of a command whose whole run takes `full`: half anywhere in the run,
/// half near its end, where the commit is. (Run times vary by 2x on a shared machine: the
/// ranges lean early so most runs are still killed.)
fn kill_time(rng: &mut ChaCha8Rng, k: usize, full: Duration) -> Duration {
    let f = if k % 2 == 0 { rng.random_range(0.0..0.9) } else { rng.random_range(0.6..1.05) };
    full.mul_f64(f)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn command(cache: &Path, args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_brdfpaint"));
    c.args(args)
        .env("BRDFPAINT_CACHE", cache)
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    c
}

/// Runs to the end; returns how long it took.
fn run(cache: &Path, args: &[&str]) -> Duration {
    let start = Instant::now();
    let out = command(cache, args).output().unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    start.elapsed()
}

/// Starts a run and SIGKILLs it after `after` (or lets it finish first). Returns whether it
/// was killed before it finished.
fn run_and_kill(cache: &Path, args: &[&str], after: Duration) -> bool {
    run_or_kill(cache, args, after).is_none()
}

/// [`run_and_kill`], returning how long the run took when it finished before the kill.
fn run_or_kill(cache: &Path, args: &[&str], after: Duration) -> Option<Duration> {
    let mut child = command(cache, args).spawn().unwrap();
    let start = Instant::now();
    while start.elapsed() < after {
        if child.try_wait().unwrap().is_some() {
            return Some(start.elapsed());
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let finished = child.try_wait().unwrap().is_some().then(|| start.elapsed());
    let _ = child.kill();
    let _ = child.wait();
    finished
}

/// The kill loop: `variants` are two argument lists writing different outputs to the same
/// place; `whole` says which variant's output is there, whole (`Some(i)`), or fails on a
/// mixed or partial one. The first variant is run to the end first.
fn kill_loop(name: &str, seed: u64, dir: &Path, variants: [Vec<String>; 2], whole: impl Fn() -> Option<usize>) {
    let cache = dir.join("cache");
    let args = |i: usize| variants[i].iter().map(String::as_str).collect::<Vec<_>>();
    // Timed on the second run: the first also fills Mesa's shader cache and our prepare cache.
    run(&cache, &args(0));
    let full = run(&cache, &args(0));
    assert_eq!(whole(), Some(0), "{name}: the first run's output");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut killed, mut old, mut new) = (0, 0, 0);
    let kills = kills();
    for k in 0..kills {
        let before = whole().unwrap_or_else(|| panic!("{name}: no whole output before kill {k}"));
        let next = 1 - before;
        let after = kill_time(&mut rng, k, full);
        killed += run_and_kill(&cache, &args(next), after) as usize;
        // What the next run does first.
        sweep_stale(dir);
        let now = whole().unwrap_or_else(|| panic!("{name}: kill {k} after {after:?} left a partial or mixed output"));
        if now == before {
            old += 1;
        } else {
            new += 1;
        }
        let temps = temporaries(dir);
        assert!(temps.is_empty(), "{name}: kill {k} after {after:?} left {temps:?}");
    }
    eprintln!("{name}: {kills} runs ({killed} killed; full run {full:?}): {old} left the old output, {new} the new one, none mixed");
    assert!(killed >= kills / 5, "{name}: only {killed} of {kills} runs were killed before they finished");
}

fn bunny() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/bunny/bunny.glb").display().to_string()
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|a| a.to_string()).collect()
}

/// A sheet's four files belong together: the same size, and a scene whose camera has their
/// aspect. Returns which of the two sizes it is.
fn sheet_variant(dir: &Path, sizes: [(u32, u32); 2]) -> Option<usize> {
    let dims: Vec<(u32, u32)> = ["outline.png", "reference.png", "mask.png"]
        .iter()
        .map(|f| image::image_dimensions(dir.join(f)).ok())
        .collect::<Option<_>>()?;
    let i = sizes.iter().position(|&s| s == dims[0])?;
    if dims.iter().any(|&d| d != dims[0]) {
        return None;
    }
    let scene = brdfpaint::scene::Scene::load(dir.join("scene.gltf")).ok()?;
    let aspect = match scene.camera.projection {
        brdfpaint::scene::Projection::Perspective { aspect, .. } => aspect?,
        brdfpaint::scene::Projection::Orthographic { xmag, ymag, .. } => xmag / ymag,
    };
    let want = sizes[i].0 as f32 / sizes[i].1 as f32;
    ((aspect - want).abs() < 1e-3 * want).then_some(i)
}

#[test]
fn sheets_are_whole_across_kills() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("sheet");
    let sizes = [(256, 256), (384, 192)];
    let variant = |(w, h): (u32, u32)| {
        strings(&["sheet", "--model", &bunny(), "--preset", "front", "--size", &format!("{w}x{h}"), "--out", s(&out)])
    };
    let painting = out.join("my-painting.png");
    kill_loop("sheet", 1, root.path(), [variant(sizes[0]), variant(sizes[1])], || {
        if !painting.exists() && out.exists() {
            std::fs::write(&painting, "the user's painting").unwrap();
        }
        assert_eq!(std::fs::read_to_string(&painting).unwrap(), "the user's painting");
        sheet_variant(&out, sizes)
    });
}

/// A fitted material with its report: loads, has report.png, and its table resolution says
/// which run made it.
fn material_variant(dir: &Path, res: [usize; 2]) -> Option<usize> {
    let m = Material::load(dir).ok()?;
    if !dir.join("report.png").is_file() || std::fs::read_to_string(dir.join("notes.txt")).ok()? != "notes" {
        return None;
    }
    res.iter().position(|&r| m.terms[0].factors[0].spec.res == r)
}

#[test]
fn fitted_materials_are_whole_with_their_report_across_kills() {
    let root = tempfile::tempdir().unwrap();
    let sheet = root.path().join("sheet");
    run(&root.path().join("cache"), &["sheet", "--model", &bunny(), "--preset", "front", "--size", "256x256", "--out", s(&sheet)]);
    let out = root.path().join("mat");
    let res = [64, 96];
    let variant = |r: usize| {
        strings(&[
            "fit",
            "--scene",
            s(&sheet.join("scene.gltf")),
            "--image",
            s(&sheet.join("reference.png")),
            "--res",
            &r.to_string(),
            "--out",
            s(&out),
        ])
    };
    kill_loop("fit", 2, root.path(), [variant(res[0]), variant(res[1])], || {
        if out.exists() && !out.join("notes.txt").exists() {
            std::fs::write(out.join("notes.txt"), "notes").unwrap();
        }
        material_variant(&out, res)
    });
}

/// Every frame of the sequence exists and has one of the two sizes, all the same.
fn sequence_variant(frames: &[PathBuf], sizes: [(u32, u32); 2]) -> Option<usize> {
    let dims: Vec<(u32, u32)> = frames.iter().map(|f| image::image_dimensions(f).ok()).collect::<Option<_>>()?;
    if dims.iter().any(|&d| d != dims[0]) {
        return None;
    }
    sizes.iter().position(|&s| s == dims[0])
}

#[test]
fn turntable_sequences_are_whole_across_kills() {
    let root = tempfile::tempdir().unwrap();
    let cache = root.path().join("cache");
    let merl = root.path().join("m.binary");
    brdfpaint::brdf::Merl::from_brdf(|_, _| [0.2, 0.3, 0.4]).write(&merl).unwrap();
    let mat = root.path().join("mat");
    run(&cache, &["fit", "--merl", s(&merl), "--density", "6", "--out", s(&mat)]);
    std::fs::remove_file(&merl).unwrap();
    let out_dir = root.path().join("frames");
    std::fs::create_dir(&out_dir).unwrap();
    let out = out_dir.join("r.png");
    let n = 12;
    let frames: Vec<PathBuf> = (0..n).map(|k| out_dir.join(format!("r-{k:03}.png"))).collect();
    let sizes = [(96, 96), (128, 128)];
    let variant = |(w, h): (u32, u32)| {
        strings(&[
            "render",
            s(&mat),
            "--model",
            &bunny(),
            "--preset",
            "front",
            "--size",
            &format!("{w}x{h}"),
            "--turntable",
            &n.to_string(),
            "--out",
            s(&out),
        ])
    };
    // Sweeps and temporaries are in the frames' directory.
    let args = [variant(sizes[0]), variant(sizes[1])];
    kill_loop("render --turntable", 3, &out_dir, args, || sequence_variant(&frames, sizes));
}

/// Every file under `dir` (relative path) with its identity (device, inode) and bytes.
fn snapshot(dir: &Path) -> std::collections::BTreeMap<PathBuf, ((u64, u64), Vec<u8>)> {
    use std::os::unix::fs::MetadataExt;
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let (path, meta) = (e.path(), e.metadata().unwrap());
            if meta.is_dir() {
                stack.push(path);
            } else {
                let bytes = std::fs::read(&path).unwrap();
                out.insert(path.strip_prefix(dir).unwrap().to_path_buf(), ((meta.dev(), meta.ino()), bytes));
            }
        }
    }
    out
}

/// Whether `dir` is a whole demo with the files `names`: exactly those files, summary.txt
/// written by the demo, every picture decodes, every material loads.
fn demo_is_whole(dir: &Path, names: &[PathBuf]) -> Result<(), String> {
    let now: Vec<PathBuf> = snapshot(dir).into_keys().collect();
    if now != names {
        return Err(format!("files differ from a demo's: {} of {}", now.len(), names.len()));
    }
    let summary = std::fs::read_to_string(dir.join("summary.txt")).map_err(|e| e.to_string())?;
    if !summary.starts_with(brdfpaint::demo::MARK) {
        return Err("summary.txt is not the demo's".into());
    }
    for name in names {
        let path = dir.join(name);
        if name.extension().is_some_and(|e| e == "png") {
            image::image_dimensions(&path).map_err(|e| format!("{}: {e}", name.display()))?;
        }
        if name.file_name().is_some_and(|f| f == "material.json") {
            Material::load(path.parent().unwrap()).map_err(|e| e.to_string())?;
        }
    }
    Ok(())
}

/// `demo` over an earlier demo, killed at random moments: after the sweep the next run does,
/// the directory is the earlier demo untouched (every file the same file, same bytes), or a
/// whole new one (every file new: none shares an inode with the earlier demo's, so a mix of
/// old and new files cannot pass); never missing or partial. No temporary is left beside it,
/// and a run to the end afterwards leaves none there or in the prepare cache.
#[test]
fn the_demo_is_whole_across_kills() {
    let root = tempfile::tempdir().unwrap();
    let (out, cache) = (root.path().join("demo"), root.path().join("cache"));
    let args = ["demo", "--out", s(&out)];
    // Timed on the second run: the first also fills Mesa's shader cache and our prepare cache.
    run(&cache, &args);
    let mut full = run(&cache, &args);
    let names: Vec<PathBuf> = snapshot(&out).into_keys().collect();
    assert!(names.len() > 50, "a demo has its sheets, paintings, materials and renders: {names:?}");
    demo_is_whole(&out, &names).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let (mut killed, mut old, mut new) = (0, 0, 0);
    let kills = kills();
    for k in 0..kills {
        let before = snapshot(&out);
        // Half anywhere, half about the end, where the commit is. A demo run (30 fits and
        // renders) varies by 2x on a shared machine, so the run time aimed at follows the
        // runs that finished.
        let after = if k % 2 == 0 { full.mul_f64(rng.random_range(0.0..1.0)) } else { full.mul_f64(rng.random_range(0.85..1.2)) };
        match run_or_kill(&cache, &args, after) {
            Some(took) => full = (full + took) / 2,
            None => killed += 1,
        }
        // What the next run does first.
        sweep_stale(root.path());
        let now = snapshot(&out);
        if now == before {
            old += 1;
            // Killed about the end before its commit: runs are slower now than `full` (the
            // machine's load rose after it was timed), and only finished runs would say so.
            if k % 2 == 1 {
                full = full.mul_f64(1.2);
            }
        } else {
            demo_is_whole(&out, &names).unwrap_or_else(|e| panic!("kill {k} after {after:?} left a partial demo: {e}"));
            let kept: Vec<&PathBuf> = now.keys().filter(|n| now[*n].0 == before[*n].0).collect();
            assert!(kept.is_empty(), "kill {k} after {after:?} left a mix: {kept:?} are the earlier demo's");
            new += 1;
        }
        let temps = temporaries(root.path());
        assert!(temps.is_empty(), "kill {k} after {after:?} left {temps:?}");
    }
    eprintln!("demo: {kills} runs ({killed} killed; full run {full:?}): {old} left the old output, {new} the new one, none mixed");
    assert!(killed >= kills / 5, "only {killed} of {kills} runs were killed before they finished");
    assert!(new > 0 || kills < 10, "no run got to its commit: the kills never tested it");
    // A run to the end after the kills: whole, and nothing hidden anywhere it writes.
    run(&cache, &args);
    demo_is_whole(&out, &names).unwrap();
    for d in [root.path(), &out, &cache] {
        assert!(temporaries(d).is_empty(), "{}: {:?}", d.display(), temporaries(d));
    }
}
