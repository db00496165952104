//! The `scatterbench` executable: the command line over the built-in methods.

fn main() -> std::process::ExitCode {
    scatterbench::main_with(methods::REGISTRY)
}
