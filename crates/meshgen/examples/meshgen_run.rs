//! Time MESHGEN on a built-in region (use --release):
//! `cargo run -p cvtmesh-meshgen --release --example meshgen_run -- circle 88 [max_iter]`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    testkit::timed_run(&cvtmesh_meshgen::Meshgen)
}
