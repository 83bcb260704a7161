//! The heartmesh command-line tool (under construction).
fn main() {
    println!("heartmesh {}", heartmesh_core::VERSION);
}
