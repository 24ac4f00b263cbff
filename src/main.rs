fn main() -> std::process::ExitCode {
    brdfpaint::cli::run()
}
