//! Diagnostics for integrators.

use super::guard;
use crate::status::Status;

/// Deliberately panics inside rodkit's C-boundary guard and returns
/// `RODKIT_STATUS_ERR_INTERNAL`, with a last-error message containing
/// "deliberate panic". It lets a host program (and rodkit's own tests) verify
/// that a bug inside rodkit reaches it as a status, never as an abort or an
/// unwind into C. Nothing is printed: the message names the panic's place
/// instead (rodkit's panic hook keeps quiet for panics its guard catches and
/// passes every other panic to the hook it replaced).
#[no_mangle]
pub extern "C" fn rodkit_diagnostic_panic() -> i32 {
    guard(|| -> crate::Result<Status> { panic!("deliberate panic from rodkit_diagnostic_panic") })
}
