//! The command-line tests' helpers: the binary, the repository, a
//! command's JSON output.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Command;

pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
}

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub fn json(args: &[&str]) -> serde_json::Value {
    let out = bin().args(args).current_dir(repo()).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Runs `args`, which must be refused as bad input: exit code 2 and one
/// line on stderr.
pub fn assert_refused(args: &[&str]) {
    let out = bin().args(args).current_dir(repo()).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
}
