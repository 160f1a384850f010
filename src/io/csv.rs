//! CSV tables: a header row of names, then one row of numbers per item,
//! comma-separated, at full precision (Rust's shortest round-trip form).

use crate::error::Result;
use std::io::Write;
use std::path::Path;

/// Write `rows` under `header` to `path` (every row as long as the header).
pub fn write_table(path: &Path, header: &[&str], rows: &[Vec<f64>]) -> Result<()> {
    let cells: Vec<Vec<Option<f64>>> = rows.iter().map(|r| r.iter().copied().map(Some).collect()).collect();
    write_cells(path, header, &cells)
}

/// Write `rows` under `header` to `path`, a `None` as an empty cell (a
/// quantity that was not given: never a made-up number).
pub fn write_cells<S: AsRef<str>>(path: &Path, header: &[S], rows: &[Vec<Option<f64>>]) -> Result<()> {
    debug_assert!(rows.iter().all(|r| r.len() == header.len()));
    let header: Vec<&str> = header.iter().map(AsRef::as_ref).collect();
    super::write_atomically(path, |w: &mut dyn Write| {
        writeln!(w, "{}", header.join(","))?;
        for row in rows {
            let cells: Vec<String> = row.iter().map(|v| v.map(|v| format!("{v:e}")).unwrap_or_default()).collect();
            writeln!(w, "{}", cells.join(","))?;
        }
        Ok(())
    })
}
