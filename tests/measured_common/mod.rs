//! Running the `brdfpaint` binary under a time limit and an address-space limit, with the
//! peak memory the kernel measured for the run.
//!
//! The kernel's peak (`ru_maxrss`) starts from the test process's own resident size at the
//! fork, so a tight bound holds only in a test binary whose other tests allocate little.
#![allow(dead_code)]

use std::io::Write;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// What one run printed and returned, and its peak resident memory.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
    pub peak_mib: u64,
}

/// Every rejected bomb stays under this peak (issue 33's target).
pub const BOMB_PEAK_MIB: u64 = 600;

/// Runs `brdfpaint` with its prepare cache in `cache`, killed (and the test failed) after
/// `limit`, under a 4 GiB address-space limit so that a run that would take gigabytes
/// fails rather than exhausts the machine. The peak is the kernel's (`wait4`).
pub fn run(cache: &Path, args: &[&str], limit: Duration) -> Run {
    run_within(cache, args, limit, 4 << 30)
}

/// [`run`] under an address-space limit of `address_space` bytes.
pub fn run_within(cache: &Path, args: &[&str], limit: Duration, address_space: libc::rlim_t) -> Run {
    let dir = tempfile::tempdir().unwrap();
    let (out, err) = (dir.path().join("out"), dir.path().join("err"));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_brdfpaint"));
    cmd.args(args)
        .env("BRDFPAINT_CACHE", cache)
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap());
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        cmd.pre_exec(move || {
            let limit = libc::rlimit { rlim_cur: address_space, rlim_max: address_space };
            if libc::setrlimit(libc::RLIMIT_AS, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    // Reaped by `wait4` below, which also gives its resource usage.
    #[allow(clippy::zombie_processes)]
    let pid = cmd.spawn().unwrap().id() as libc::pid_t;
    let start = Instant::now();
    let (mut status, mut usage) = (0, unsafe { std::mem::zeroed::<libc::rusage>() });
    loop {
        // SAFETY: polls our own child (std's handle to it was dropped without waiting).
        let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if r == pid {
            break;
        }
        if start.elapsed() > limit {
            // SAFETY: our own child, not yet reaped.
            unsafe {
                libc::kill(pid, libc::SIGKILL);
                libc::wait4(pid, &mut status, 0, &mut usage);
            }
            panic!("brdfpaint {args:?} hung for {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let code = if libc::WIFEXITED(status) { libc::WEXITSTATUS(status) } else { -libc::WTERMSIG(status) };
    Run {
        code,
        stdout: std::fs::read_to_string(out).unwrap(),
        stderr: std::fs::read_to_string(err).unwrap(),
        // ru_maxrss is in kilobytes on Linux.
        peak_mib: usage.ru_maxrss as u64 >> 10,
    }
}

pub const MINUTE: Duration = Duration::from_secs(60);

/// Exit 1 and one line on stderr that contains every one of `parts`.
pub fn assert_one_line_error(r: &Run, parts: &[&str]) {
    assert_eq!(r.code, 1, "{}", r.stderr);
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    assert!(r.stderr.starts_with("error: ") && !r.stderr.contains("internal error"), "{}", r.stderr);
    for p in parts {
        assert!(r.stderr.contains(p), "{p:?} not in {}", r.stderr);
    }
}

/// A bomb is refused with one line, under [`BOMB_PEAK_MIB`].
pub fn assert_refused_small(r: &Run, parts: &[&str]) {
    assert_one_line_error(r, parts);
    assert!(r.peak_mib < BOMB_PEAK_MIB, "peaked at {} MiB: {}", r.peak_mib, r.stderr);
}

/// An RGB PNG (8- or 16-bit) of `w` × `h` pixels, `colour(x, y)` each, written a row at a time.
pub fn write_png(path: &Path, w: u32, h: u32, sixteen: bool, colour: impl Fn(u32, u32) -> [u16; 3]) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut encoder = png::Encoder::new(file, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(if sixteen { png::BitDepth::Sixteen } else { png::BitDepth::Eight });
    let mut writer = encoder.write_header().unwrap();
    let mut stream = writer.stream_writer().unwrap();
    for y in 0..h {
        let row: Vec<u8> = (0..w)
            .flat_map(|x| colour(x, y))
            .flat_map(|c| if sixteen { c.to_be_bytes().to_vec() } else { vec![c as u8] })
            .collect();
        stream.write_all(&row).unwrap();
    }
    stream.finish().unwrap();
}
