//! CSV tables: a header row of names, then one row of numbers per item,
//! comma-separated, at full precision (Rust's shortest round-trip form).

use crate::error::Result;
use std::io::Write;
use std::path::Path;

/// Write `rows` under `header` to `path` (every row as long as the header).
pub fn write_table(path: &Path, header: &[&str], rows: &[Vec<f64>]) -> Result<()> {
    debug_assert!(rows.iter().all(|r| r.len() == header.len()));
    super::write_atomically(path, |w: &mut dyn Write| {
        writeln!(w, "{}", header.join(","))?;
        for row in rows {
            let cells: Vec<String> = row.iter().map(|v| format!("{v:e}")).collect();
            writeln!(w, "{}", cells.join(","))?;
        }
        Ok(())
    })
}
