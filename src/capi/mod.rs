//! The C ABI (`../shared/spec/c-api.md`): every `extern "C"` function and all
//! `unsafe` code of rodkit. The modules below wrap safe Rust; none of them
//! holds physics.
//!
//! Every exported function runs its body inside [`guard`] (or
//! [`guard_value`]), which catches panics (→ `RODKIT_STATUS_ERR_INTERNAL`
//! with the panic message) and routes errors to the one error channel, the
//! thread-local last-error message of [`error`]. A unit test checks that no
//! exported function bypasses the guard.
#![allow(unsafe_code)]

pub mod diagnostic;
pub mod dna;
pub mod electrostatics;
pub mod error;
pub mod rod;
pub mod supercoil;
pub mod tube;
pub mod tube_scene;
pub mod version;

use crate::error::{Error, Result};
use crate::status::Status;
use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `body` for an exported fallible function: clears the last error,
/// catches panics, records the message of a failure, returns the status code.
pub(crate) fn guard(body: impl FnOnce() -> Result<Status>) -> i32 {
    error::clear_last_error();
    guard_preserving_error(body)
}

/// [`guard`] without clearing the last error on entry: for the accessor that
/// copies that message out.
pub(crate) fn guard_preserving_error(body: impl FnOnce() -> Result<Status>) -> i32 {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(status)) => status.code(),
        Ok(Err(e)) => {
            error::set_last_error(&e.message);
            e.status.code()
        }
        Err(payload) => {
            error::set_last_error(&format!("internal error (panic): {}", panic_message(&*payload)));
            Status::ErrInternal.code()
        }
    }
}

/// For the few infallible exports that return a value instead of a status
/// (and must not clear the last error, e.g. the error accessors themselves):
/// a panic yields `fallback`.
pub(crate) fn guard_value<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "non-string panic payload".to_string()
    }
}

/// Borrow a required input struct.
///
/// # Safety
/// `ptr` must be NULL or point to a valid, initialised `T` for the call.
pub(crate) unsafe fn arg_ref<'a, T>(name: &str, ptr: *const T) -> Result<&'a T> {
    ptr.as_ref().ok_or_else(|| null_error(name))
}

/// Borrow a required output struct.
///
/// # Safety
/// `ptr` must be NULL or point to writable memory for one `T`.
pub(crate) unsafe fn arg_mut<'a, T>(name: &str, ptr: *mut T) -> Result<&'a mut T> {
    ptr.as_mut().ok_or_else(|| null_error(name))
}

/// Qualify the argument named in an error message with the C struct it came
/// from (`argument \`e2\`` → `argument \`spec.e2\``), so a C caller sees the
/// field it set.
pub(crate) fn qualify_argument(mut e: Error, prefix: &str) -> Error {
    e.message = e.message.replacen("argument `", &format!("argument `{prefix}"), 1);
    e
}

pub(crate) fn null_error(name: &str) -> Error {
    Error::new(Status::ErrNullPointer, format!("argument `{name}` is NULL"))
}

/// Write a rows×cols column-major matrix into a caller array with leading
/// dimension `ld` (≥ rows). Entries between rows and ld are left untouched.
///
/// # Safety
/// `ptr` must be NULL or point to at least ld·(cols − 1) + rows writable doubles.
pub(crate) unsafe fn write_matrix(
    name: &str,
    ptr: *mut f64,
    ld: i64,
    ld_name: &str,
    rows: usize,
    cols: usize,
    column_major: &[f64],
) -> Result<()> {
    debug_assert_eq!(column_major.len(), rows * cols);
    crate::error::count_in_range(ld_name, ld, rows as i64, i64::MAX / 64)?;
    if ptr.is_null() {
        return Err(null_error(name));
    }
    let ld = ld as usize;
    let out = std::slice::from_raw_parts_mut(ptr, ld * (cols - 1) + rows);
    for j in 0..cols {
        out[j * ld..j * ld + rows].copy_from_slice(&column_major[j * rows..(j + 1) * rows]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    /// c-api.md: "Every exported function runs inside catch_unwind (one
    /// macro, so none is forgotten)". Reference: the sources themselves —
    /// every `extern "C" fn` body must call `guard(` or `guard_value(`.
    #[test]
    fn every_export_is_guarded() {
        let sources = [
            include_str!("diagnostic.rs"),
            include_str!("dna.rs"),
            include_str!("electrostatics.rs"),
            include_str!("error.rs"),
            include_str!("rod.rs"),
            include_str!("supercoil.rs"),
            include_str!("tube.rs"),
            include_str!("tube_scene.rs"),
            include_str!("version.rs"),
        ];
        let mut exports = 0;
        for src in sources {
            for chunk in src.split("extern \"C\" fn ").skip(1) {
                exports += 1;
                let name = chunk.split('(').next().unwrap();
                // The body runs up to the next top-level item.
                let body = chunk.split("\n}\n").next().unwrap();
                assert!(
                    body.contains("guard(")
                        || body.contains("guard_value(")
                        || body.contains("guard_preserving_error("),
                    "exported function {name} does not run inside guard()"
                );
            }
        }
        assert!(exports >= 10, "found only {exports} exports: parser out of date?");
    }
}
