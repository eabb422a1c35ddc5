//! The `dalembert` binary: a thin front over the library (contract.md).

mod cli;

fn main() {
    let code = cli::run(std::env::args().collect());
    std::process::exit(code);
}
