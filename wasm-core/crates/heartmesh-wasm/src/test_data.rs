//! Where the tests find the shared fixtures (test builds only).

/// `shared/data/<rel>`: the nearest ancestor of this crate holding it (as the CLI's tests), so a
/// checkout with ../shared beside it and a git worktree deeper down both find it.
pub fn data(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.join("README.md").is_file())
        .expect("shared/data not found above CARGO_MANIFEST_DIR")
        .join(rel)
}
