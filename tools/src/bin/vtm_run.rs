//! Time VTM on a built-in region (use --release):
//! `cargo run --release -p cvtmesh-tools --bin vtm_run -- circle 88 [max_iter]`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    testkit::timed_run(&vtm::Vtm::default())
}
