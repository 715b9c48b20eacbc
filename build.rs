//! Records the commit aa-lab was built from (when built from a git checkout) so that exported
//! images and reports can name their build, with `-dirty` after it when the sources the binary
//! is built from (`src/`, `build.rs`, `Cargo.toml`, `Cargo.lock`) differ from that commit: a
//! report from a locally changed build must not pass for the commit's.

use std::process::Command;

/// The files whose changes make a build differ from its commit.
const SOURCES: [&str; 4] = ["src", "build.rs", "Cargo.toml", "Cargo.lock"];

fn git(args: &[&str]) -> Option<String> {
    Command::new("git")
        .args(args)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
}

fn main() {
    let hash = git(&["rev-parse", "--short=12", "HEAD"]).unwrap_or_default();
    let hash = hash.trim();
    let mut status = vec!["status", "--porcelain", "--untracked-files=no", "--"];
    status.extend(SOURCES);
    let dirty = !hash.is_empty() && git(&status).is_some_and(|s| !s.trim().is_empty());
    let id = if dirty {
        format!("{hash}-dirty")
    } else {
        hash.to_string()
    };
    println!("cargo:rustc-env=AA_LAB_GIT_HASH={id}");
    println!("cargo:rerun-if-changed=.git/HEAD");
    println!("cargo:rerun-if-changed=.git/refs/heads");
    println!("cargo:rerun-if-changed=.git/index");
    for source in SOURCES {
        println!("cargo:rerun-if-changed={source}");
    }
}
