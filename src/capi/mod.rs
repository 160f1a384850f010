//! The C ABI (`../shared/spec/c-api.md`): every `extern "C"` function and all
//! `unsafe` code of rodkit. The modules below wrap safe Rust, one file per C
//! object; none of them holds physics. The argument plumbing they share
//! (flags, enums, arrays, matrices, size queries, handles) is in [`args`].
//!
//! Every exported function runs its body inside [`guard`] (or
//! [`guard_value`]), which catches panics (→ `RODKIT_STATUS_ERR_INTERNAL`
//! with the panic message) and routes errors to the one error channel, the
//! thread-local last-error message of [`error`]. A unit test checks that no
//! exported function bypasses the guard.
//!
//! # Safety
//!
//! Every `extern "C"` function has the same safety contract, stated once
//! here and in c-api.md: pointers valid for the call, arrays of the stated
//! lengths.
#![allow(unsafe_code)]

pub(crate) mod args;

// The C objects, one file each. cbindgen writes the functions in the order it
// reads these modules: this is the header's order. The blank lines keep
// rustfmt from sorting the groups into one.
pub mod diagnostic;
pub mod dna_fit;

pub mod curve;
pub mod error;
pub mod rod_spec;

pub mod continuation;
pub mod rod;

pub mod accuracy;
pub mod branch;
pub mod branch_record;
pub mod output;
pub mod supercoil;
pub mod supercoil_curve;
pub mod tweezers;

pub mod equilibrium;
pub mod thin_tube;
pub mod wall_material;

pub mod tube;
pub mod version;

use crate::error::Result;
use crate::status::Status;
use std::any::Any;
use std::cell::{Cell, RefCell};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Once;

/// Runs `body` for an exported fallible function: clears the last error,
/// catches panics, records the message of a failure, returns the status code.
/// A success (status ≥ 0) leaves the channel empty even when a callback run
/// inside `body` made a failing rodkit call on this thread (the header
/// promises the empty string after every successful call).
pub(crate) fn guard(body: impl FnOnce() -> Result<Status>) -> i32 {
    error::clear_last_error();
    let code = guard_preserving_error(body);
    if code >= 0 {
        error::clear_last_error();
    }
    code
}

/// [`guard`] without clearing the last error on entry: for the accessor that
/// copies that message out.
pub(crate) fn guard_preserving_error(body: impl FnOnce() -> Result<Status>) -> i32 {
    match guarded(body) {
        Ok(Ok(status)) => status.code(),
        Ok(Err(e)) => {
            error::set_last_error(&e.message);
            e.status.code()
        }
        Err((payload, place)) => {
            let at = place.map(|p| format!(" at {p}")).unwrap_or_default();
            error::set_last_error(&format!("internal error (panic{at}): {}", panic_message(&*payload)));
            Status::ErrInternal.code()
        }
    }
}

/// For the few infallible exports that return a value instead of a status
/// (and must not clear the last error, e.g. the error accessors themselves):
/// a panic yields `fallback`.
pub(crate) fn guard_value<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    guarded(body).unwrap_or(fallback)
}

thread_local! {
    /// Guarded calls running on this thread (callbacks nest them).
    static GUARDED: Cell<u32> = const { Cell::new(0) };
    /// Where the last panic inside a guarded call happened.
    static PANIC_PLACE: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// `body` under catch_unwind, with the panic's place. A panic caught here
/// becomes a status and a message on the error channel, so it prints
/// nothing on the host's stderr (no message, no backtrace even with
/// RUST_BACKTRACE set): a hook installed once passes panics outside
/// guarded calls to the hook it replaced and keeps only the place of those
/// inside.
fn guarded<T>(body: impl FnOnce() -> T) -> std::result::Result<T, (Box<dyn Any + Send>, Option<String>)> {
    static QUIET: Once = Once::new();
    QUIET.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if GUARDED.with(|g| g.get()) > 0 {
                let place = info.location().map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()));
                PANIC_PLACE.with(|p| *p.borrow_mut() = place);
            } else {
                previous(info);
            }
        }));
    });
    struct Depth;
    impl Drop for Depth {
        fn drop(&mut self) {
            GUARDED.with(|g| g.set(g.get() - 1));
        }
    }
    GUARDED.with(|g| g.set(g.get() + 1));
    let depth = Depth;
    let result = catch_unwind(AssertUnwindSafe(body));
    drop(depth);
    result.map_err(|payload| (payload, PANIC_PLACE.with(|p| p.borrow_mut().take())))
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

#[cfg(test)]
mod tests {
    /// c-api.md: "Every exported function runs inside catch_unwind (one
    /// macro, so none is forgotten)". Reference: the sources themselves —
    /// every `extern "C" fn` body must call `guard(` or `guard_value(`.
    #[test]
    fn every_export_is_guarded() {
        let sources = [
            include_str!("diagnostic.rs"),
            include_str!("dna_fit.rs"),
            include_str!("curve.rs"),
            include_str!("error.rs"),
            include_str!("rod_spec.rs"),
            include_str!("continuation.rs"),
            include_str!("rod.rs"),
            include_str!("branch_record.rs"),
            include_str!("branch.rs"),
            include_str!("supercoil.rs"),
            include_str!("supercoil_curve.rs"),
            include_str!("equilibrium.rs"),
            include_str!("thin_tube.rs"),
            include_str!("wall_material.rs"),
            include_str!("tube.rs"),
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
