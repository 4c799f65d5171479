//! Records the git commit the crate is built from (`SOFTWAY_GIT_COMMIT`, read by
//! `softway::GIT_COMMIT`) when built from a git checkout; nothing otherwise.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
}

fn main() {
    println!("cargo:rerun-if-env-changed=SOFTWAY_GIT_COMMIT");
    // ... and when the sources change (the dirty mark; the crate is compiled again then
    // anyway).
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=Cargo.toml");
    // Built again when HEAD moves (a commit, a checkout) or the index changes (a staged or
    // committed change: the dirty mark).
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        println!("cargo:rerun-if-changed={dir}/HEAD");
        println!("cargo:rerun-if-changed={dir}/index");
        if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]) {
            if let Some(common) = git(&["rev-parse", "--git-common-dir"]) {
                println!("cargo:rerun-if-changed={common}/{r}");
            }
        }
    }
    if let Some(c) = git(&["describe", "--always", "--dirty", "--abbrev=12"]) {
        println!("cargo:rustc-env=SOFTWAY_GIT_COMMIT={c}");
    }
}
