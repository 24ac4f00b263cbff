//! The `brdfpaint` binary: the command line ([`cli`]) over the library.

mod cli;

fn main() -> std::process::ExitCode {
    // Printing into a closed pipe (`brdfpaint fit ... | head`) ends the process quietly, as
    // it does for other command-line tools, instead of failing a write.
    #[cfg(unix)]
    // SAFETY: restores the default disposition of one signal before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // A prepare allocates and frees its matrices (up to tens of MB) once per fit or stroke.
    // glibc hands such blocks back to the kernel, and every prepare then faults its pages in
    // again, zeroed; kept in the heap they are reused (BENCHMARKS.md, the peer section).
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters, before any thread starts.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
    }
    // A panic is a bug, never the answer to bad input; say so in one line, not a backtrace.
    std::panic::set_hook(Box::new(|info| {
        // A panic the library catches (inside the gltf crate) becomes its one-line error.
        if !brdfpaint::error::panic_is_caught() {
            eprintln!("error: internal error (please report): {info}");
        }
    }));
    brdfpaint::note::set_handler(|note| eprintln!("note: {note}"));
    cli::run()
}
