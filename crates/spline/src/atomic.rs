//! Writing output files so that a failure never leaves a partial file behind:
//! `mesh::atomic` with the bytes ready.

use std::io::{self, Write};
use std::path::Path;

/// Writes `bytes` to `path` through a temporary file beside it, renamed onto
/// `path` only once everything was written and synced.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
    mesh::atomic::write_atomically(path, |w| w.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_and_fails_cleanly() {
        let dir = std::env::temp_dir().join(format!("spline-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("a.txt");
        write_atomically(&target, b"ok").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"ok");
        // A directory that does not exist: an error, and nothing left behind.
        let bad = dir.join("missing").join("b.txt");
        assert!(write_atomically(&bad, b"x").is_err());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
