//! Diagnostics for integrators.

use super::guard;
use crate::status::Status;

/// Deliberately panics inside rodkit's C-boundary guard and returns
/// `RODKIT_STATUS_ERR_INTERNAL`, with a last-error message containing
/// "deliberate panic". It lets a host program (and rodkit's own tests) verify
/// that a bug inside rodkit reaches it as a status, never as an abort or an
/// unwind into C. The Rust runtime's default panic hook also prints one line
/// to stderr (rodkit does not replace the process-wide hook).
#[no_mangle]
pub extern "C" fn rodkit_diagnostic_panic() -> i32 {
    guard(|| -> crate::Result<Status> { panic!("deliberate panic from rodkit_diagnostic_panic") })
}
