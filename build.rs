//! Records the git commit the crate is built from (`SOFTWAY_GIT_COMMIT`, read by
//! `softway::GIT_COMMIT`) when built from a git checkout; nothing otherwise.
//!
//! The script must not make the next cargo command build the crate again: it reads the
//! repository without writing to it and watches only files that git changes when HEAD
//! moves. `git describe --dirty` refreshes and rewrites `.git/index` whenever a file's stat
//! data changed (on a fresh clone, its first run does), even under `--no-optional-locks`;
//! so the commit comes from `git describe` without `--dirty`, and the dirty mark from
//! `git status`, which under `GIT_OPTIONAL_LOCKS=0` compares in memory and leaves the index
//! alone. The index itself is not watched.

use std::path::Path;
use std::process::Command;

/// The files and folders the crate is compiled from: a change to any of them builds the
/// crate again anyway, so the script runs again with it and the dirty mark follows them.
const SOURCES: [&str; 5] = ["src", "crates", "build.rs", "Cargo.toml", "Cargo.lock"];

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .env("GIT_OPTIONAL_LOCKS", "0")
        .args(args)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Watches `path` if it exists (a missing path would run the script, and build the crate,
/// on every cargo command).
fn watch(path: &str) {
    if Path::new(path).exists() {
        println!("cargo:rerun-if-changed={path}");
    }
}

fn main() {
    println!("cargo:rerun-if-env-changed=SOFTWAY_GIT_COMMIT");
    for s in SOURCES {
        watch(s);
    }
    let Some(dir) = git(&["rev-parse", "--git-dir"]).filter(|s| !s.is_empty()) else {
        return;
    };
    // HEAD moves: `HEAD` changes on a checkout of another branch or commit, the branch's
    // ref on a commit (git writes it loose, even when it was packed), `logs/HEAD` (the
    // reflog) on every move of HEAD.
    watch(&format!("{dir}/HEAD"));
    watch(&format!("{dir}/logs/HEAD"));
    if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]).filter(|s| !s.is_empty()) {
        if let Some(common) = git(&["rev-parse", "--git-common-dir"]).filter(|s| !s.is_empty()) {
            watch(&format!("{common}/{r}"));
            watch(&format!("{common}/packed-refs"));
        }
    }
    let Some(commit) = git(&["describe", "--always", "--abbrev=12"]).filter(|s| !s.is_empty())
    else {
        return;
    };
    // Dirty: a tracked source differs from HEAD (staged or not).
    let mut status = vec!["status", "--porcelain", "--untracked-files=no", "--"];
    status.extend(SOURCES);
    let dirty = git(&status).is_some_and(|s| !s.is_empty());
    let suffix = if dirty { "-dirty" } else { "" };
    println!("cargo:rustc-env=SOFTWAY_GIT_COMMIT={commit}{suffix}");
}
