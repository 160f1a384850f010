//! Files for other tools: shapes as legacy VTK polydata (ParaView, VisIt)
//! and tables as CSV. Opt-in and path-given: rodkit writes nothing unless
//! asked, and a file that cannot be written is an error naming the path and
//! the system's reason (`Status::ErrIo`), never a partial file left behind
//! silently (the file is written in full to a temporary name beside it and
//! renamed).

pub mod csv;
pub mod vtk;

use crate::error::{Error, Result};
use crate::status::Status;
use std::io::Write;
use std::path::Path;

/// Write `contents(writer)` to `path` through a temporary file beside it,
/// renamed when complete.
pub(crate) fn write_atomically(
    path: &Path,
    contents: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let io_error = |what: &str, e: std::io::Error| {
        Error::new(Status::ErrIo, format!("could not {what} `{}`: {e}", path.display()))
    };
    let name =
        path.file_name().ok_or_else(|| Error::new(Status::ErrIo, format!("`{}` names no file", path.display())))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let file = std::fs::File::create(&tmp).map_err(|e| io_error("create", e))?;
    let mut w = std::io::BufWriter::new(file);
    let written = contents(&mut w).and_then(|_| w.flush());
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(io_error("write", e));
    }
    drop(w);
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io_error("rename into", e)
    })
}
