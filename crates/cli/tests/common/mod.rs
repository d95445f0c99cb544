//! Scaffolding shared by the command-line tests: the binary under test and scratch directories.

use std::fs;
use std::path::PathBuf;
use std::process::Command;

/// The `radiosity` binary under test, not yet run.
pub fn radiosity() -> Command {
    Command::new(env!("CARGO_BIN_EXE_radiosity"))
}

/// A fresh empty directory for one test, `radiosity-test-NAME-PID` in the temporary directory
/// (the process id keeps concurrent test binaries apart; `name` keeps the tests of one apart).
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("radiosity-test-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}
