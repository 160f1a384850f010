//! The one error channel: a thread-local message describing the last failure
//! on the calling thread (the only global state rodkit has, as c-api.md allows).
//!
//! Every fallible rodkit function clears it on entry and sets it on failure,
//! so after a successful call it is the empty string. The accessors below do
//! not clear it.

use super::args::null_error;
use super::{guard_preserving_error, guard_value};
use crate::error;
use crate::status::Status;
use std::cell::RefCell;
use std::ffi::{c_char, CString};

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

pub(crate) fn clear_last_error() {
    LAST_ERROR.with(|m| *m.borrow_mut() = CString::default());
}

pub(crate) fn set_last_error(message: &str) {
    let c = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
    LAST_ERROR.with(|m| *m.borrow_mut() = c);
}

/// The message of the last failure on this thread (the Rust API's view).
pub fn last_error_message() -> String {
    LAST_ERROR.with(|m| m.borrow().to_string_lossy().into_owned())
}

/// Human-readable description of a status code (never NULL; static storage;
/// "unknown rodkit status code" for codes rodkit does not define).
#[no_mangle]
pub extern "C" fn rodkit_status_string(code: i32) -> *const c_char {
    const UNKNOWN: &str = "unknown rodkit status code\0";
    guard_value(UNKNOWN.as_ptr().cast(), || {
        Status::from_code(code).map_or(UNKNOWN, Status::message_nul).as_ptr().cast()
    })
}

/// Message describing the last failure of a rodkit call on the calling
/// thread, naming the offending argument and value where there is one; the
/// empty string if the last call succeeded. Never NULL.
///
/// The pointer is owned by rodkit and stays valid until the next rodkit call
/// on the same thread other than `rodkit_last_error_message`,
/// `rodkit_last_error_copy` and `rodkit_status_string`. Copy it if you need it
/// longer (or use `rodkit_last_error_copy`).
#[no_mangle]
pub extern "C" fn rodkit_last_error_message() -> *const c_char {
    guard_value(c"internal error while reading the last error".as_ptr(), || LAST_ERROR.with(|m| m.borrow().as_ptr()))
}

/// Copy the last-error message into a caller buffer of `capacity` bytes
/// (`capacity` ≥ 1), always NUL-terminated. `length` (may be NULL) receives
/// the full message length in bytes, without the NUL.
///
/// Returns `RODKIT_STATUS_OK`, or `RODKIT_STATUS_INFO_TRUNCATED` (> 0) when the
/// message was cut to `capacity − 1` bytes. This call leaves the message
/// unchanged unless it fails itself (NULL `buffer`, `capacity` < 1).
#[no_mangle]
pub unsafe extern "C" fn rodkit_last_error_copy(buffer: *mut c_char, capacity: i64, length: *mut i64) -> i32 {
    guard_preserving_error(|| LAST_ERROR.with(|m| copy_message(m.borrow().as_bytes(), buffer, capacity, length)))
}

/// Copy `bytes` into a caller buffer of `capacity` bytes (≥ 1), always
/// NUL-terminated; `length` (may be NULL) receives the full length. OK, or
/// InfoTruncated when it was cut to `capacity − 1` bytes. The one copy of
/// a message into C storage (the last error, a run's failure).
///
/// # Safety
/// `buffer`, when not NULL, must hold `capacity` bytes; `length`, when not
/// NULL, must be writable.
pub(crate) unsafe fn copy_message(
    bytes: &[u8],
    buffer: *mut c_char,
    capacity: i64,
    length: *mut i64,
) -> error::Result<Status> {
    if buffer.is_null() {
        return Err(null_error("buffer"));
    }
    error::dimension("capacity", capacity, 1, i64::MAX)?;
    let n = bytes.len().min(capacity as usize - 1);
    let out = std::slice::from_raw_parts_mut(buffer.cast::<u8>(), n + 1);
    out[..n].copy_from_slice(&bytes[..n]);
    out[n] = 0;
    if let Some(len) = length.as_mut() {
        *len = bytes.len() as i64;
    }
    Ok(if n < bytes.len() { Status::InfoTruncated } else { Status::Ok })
}
