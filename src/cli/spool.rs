//! Output in the making, spooled to an unnamed temporary file so that memory does not
//! grow with the number of rows and a refusal still leaves stdout empty (contract.md):
//! `integrate` and `check` copy their spools to stdout only once the whole answer is proved.

use crate::Error;
use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};

/// A temporary file for output in the making: removed from the file system as soon as it
/// is open (on Unix), and in any case when dropped.
pub struct Spool {
    pub out: BufWriter<File>,
    path: std::path::PathBuf,
}

impl Spool {
    pub fn new(tag: &str) -> Result<Spool, Error> {
        let dir = std::env::temp_dir();
        let stamp = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path = dir.join(format!(
            "dalembert-{}-{stamp}-{tag}.tmp",
            std::process::id()
        ));
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(&path)
            .map_err(|e| {
                Error::input(format!(
                    "cannot create a temporary file in {}: {e}",
                    dir.display()
                ))
            })?;
        // an open file needs no name on Unix: nothing is left behind even if killed
        #[cfg(unix)]
        let _ = std::fs::remove_file(&path);
        Ok(Spool {
            out: BufWriter::new(file),
            path,
        })
    }

    /// Append everything written so far to `to`.
    pub fn copy_to(&mut self, to: &mut impl Write) -> std::io::Result<()> {
        self.out.flush()?;
        let f = self.out.get_mut();
        f.seek(SeekFrom::Start(0))?;
        std::io::copy(&mut Read::by_ref(f), to)?;
        Ok(())
    }
}

impl Write for Spool {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.out.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

impl Drop for Spool {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}
