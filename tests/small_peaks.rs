//! Issue 33's smaller item: pictures refused from their headers or a row at a time, within a
//! few megabytes. A binary of its own, because the kernel's peak for a run starts from the
//! test process's resident size at the fork (see `measured_common`), and other tests'
//! buffers would count.

mod measured_common;

use measured_common::*;

/// Smaller item: a 4096² 16-bit PNG of background (130 KB) took 547 MB before `fit
/// --lit-sphere` refused it; it is now read a row at a time into the 512² picture fitted.
#[test]
fn a_large_background_png_is_refused_in_a_few_megabytes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("background.png");
    write_png(&path, 4096, 4096, true, |_, _| [32768, 16384, 8192]);
    let r = run(dir.path(), &["fit", "--lit-sphere", s(&path), "--out", s(&dir.path().join("out"))], MINUTE);
    assert_one_line_error(&r, &["background.png is all background: no sphere to find"]);
    assert!(r.peak_mib < 100, "peaked at {} MiB", r.peak_mib);

    // A painting whose aspect disagrees with its scene's camera is refused from its header.
    let sheet = dir.path().join("sheet");
    let r = run(dir.path(), &["sheet", "--model", "sphere", "--size", "64x64", "--out", s(&sheet)], MINUTE);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let wide = dir.path().join("wide.png");
    write_png(&wide, 4096, 2048, true, |_, _| [32768, 16384, 8192]);
    let r = run(dir.path(), &["fit", "--scene", s(&sheet.join("scene.gltf")), "--image", s(&wide), "--out", s(&dir.path().join("mat"))], MINUTE);
    assert_one_line_error(&r, &["wide.png", "4096x2048"]);
    assert!(r.peak_mib < 100, "peaked at {} MiB", r.peak_mib);
}
