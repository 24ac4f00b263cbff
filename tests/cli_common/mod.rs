//! Running the `brdfpaint` binary from integration tests, as a user runs it.

use std::path::Path;
use std::process::Command;

/// What one run printed and returned.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Run `brdfpaint` with `args`, its prepare cache in `cache`, on Mesa's software device.
pub fn brdfpaint(cache: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_brdfpaint"))
        .args(args)
        .env("BRDFPAINT_CACHE", cache)
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .output()
        .expect("run brdfpaint");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into(),
        stderr: String::from_utf8_lossy(&out.stderr).into(),
    }
}
