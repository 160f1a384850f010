//! Legacy VTK polydata (`# vtk DataFile Version 3.0`, ASCII): one polyline
//! per shape, and per-shape values as cell data. Coordinates at full
//! precision (%.17g round-trips every double).

use crate::error::{Error, Result};
use crate::status::Status;
use std::io::Write;
use std::path::Path;

/// Write `shapes` (each a polyline of points) to `path`, with one value per
/// shape for each named scalar (`cell_scalars`: name without spaces, values).
pub fn write_polylines(
    path: &Path,
    title: &str,
    shapes: &[Vec<[f64; 3]>],
    cell_scalars: &[(&str, Vec<f64>)],
) -> Result<()> {
    for (name, values) in cell_scalars {
        if values.len() != shapes.len() || name.is_empty() || name.contains(char::is_whitespace) {
            return Err(Error::new(
                Status::ErrInternal,
                format!("VTK cell data `{name}`: {} values for {} shapes", values.len(), shapes.len()),
            ));
        }
    }
    let points: usize = shapes.iter().map(Vec::len).sum();
    // The header's title line is one line of at most 255 characters.
    let title: String = title.chars().filter(|c| *c != '\n').take(255).collect();
    super::write_atomically(path, |w: &mut dyn Write| {
        writeln!(w, "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET POLYDATA\nPOINTS {points} double")?;
        for p in shapes.iter().flatten() {
            writeln!(w, "{:e} {:e} {:e}", p[0], p[1], p[2])?;
        }
        writeln!(w, "LINES {} {}", shapes.len(), points + shapes.len())?;
        let mut first = 0;
        for shape in shapes {
            write!(w, "{}", shape.len())?;
            for i in first..first + shape.len() {
                write!(w, " {i}")?;
            }
            writeln!(w)?;
            first += shape.len();
        }
        if !cell_scalars.is_empty() {
            writeln!(w, "CELL_DATA {}", shapes.len())?;
            for (name, values) in cell_scalars {
                writeln!(w, "SCALARS {name} double 1\nLOOKUP_TABLE default")?;
                for v in values {
                    writeln!(w, "{v:e}")?;
                }
            }
        }
        Ok(())
    })
}
