//! The argument plumbing every C function shares, in one place: borrowed
//! input and output structs, 0/1 flags, C enums from `int32_t`, arrays with
//! their length checks, matrices with a leading dimension, node positions,
//! the size-query/copy-out pattern, and owned handles. Each check names the
//! argument and the bad value (c-api.md "Status and errors").

use crate::error::{self, Error, Result};
use crate::status::Status;
use std::ffi::{c_char, CStr};
use std::fmt::Display;
use std::path::PathBuf;

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

/// `argument \`name\` out of range: must be <what> (got v)`: an argument
/// outside the values it may take (`what` states them).
pub(crate) fn must_be(name: &str, what: &str, v: impl Display) -> Error {
    Error::new(Status::ErrOutOfRange, format!("argument `{name}` out of range: must be {what} (got {v})"))
}

/// Every one of the named doubles must be finite (ERR_NOT_FINITE naming the
/// first that is not, by its C field name).
pub(crate) fn finite_fields(fields: &[(&str, f64)]) -> Result<()> {
    fields.iter().try_for_each(|&(name, v)| error::finite(name, v).map(drop))
}

/// A 0/1 switch.
pub(crate) fn flag(name: &str, v: i32) -> Result<bool> {
    match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(must_be(name, "0 or 1", v)),
    }
}

/// A value that may be zero but not negative (NaN passes: check finiteness
/// first where it matters).
pub(crate) fn non_negative(name: &str, v: f64) -> Result<f64> {
    if v < 0.0 {
        return Err(must_be(name, "≥ 0", format_args!("{v:e}")));
    }
    Ok(v)
}

/// A C enum (`#[repr(i32)]`, fields of type `int32_t` in the specs): the
/// values a caller may pass and how a wrong one is described.
pub(crate) trait CEnum: Copy + 'static {
    /// The accepted variants.
    const ALL: &'static [Self];
    /// What the argument must be, for the message (`a RodkitLoadFrame 0…2`).
    const WHAT: &'static str;
    fn code(self) -> i32;
    /// The error for a value that is none of [`CEnum::ALL`].
    fn invalid(name: &str, v: i32) -> Error {
        must_be(name, Self::WHAT, v)
    }
}

/// Implements [`CEnum`] for a fieldless `#[repr(i32)]` enum.
macro_rules! c_enum {
    ($t:ty, $what:expr, [$($v:expr),+ $(,)?]) => {
        impl $crate::capi::args::CEnum for $t {
            const ALL: &'static [Self] = &[$($v),+];
            const WHAT: &'static str = $what;
            fn code(self) -> i32 {
                self as i32
            }
        }
    };
}
pub(crate) use c_enum;

/// The variant of `E` that a C caller passed as `v`.
pub(crate) fn enum_arg<E: CEnum>(name: &str, v: i32) -> Result<E> {
    E::ALL.iter().copied().find(|e| e.code() == v).ok_or_else(|| E::invalid(name, v))
}

/// An array length (or other count) that must equal what the object has.
pub(crate) fn check_len(name: &str, got: i64, want: i64) -> Result<()> {
    if got != want {
        return Err(Error::new(Status::ErrInvalidDimension, format!("argument `{name}` must be {want} (got {got})")));
    }
    Ok(())
}

/// A caller's input array of `n` doubles, not checked for finiteness.
///
/// # Safety
/// `p` must be NULL or point to `n` readable doubles.
pub(crate) unsafe fn in_array<'a>(name: &str, p: *const f64, n: i64) -> Result<&'a [f64]> {
    if p.is_null() {
        return Err(null_error(name));
    }
    Ok(std::slice::from_raw_parts(p, n as usize))
}

/// A caller's input array of `n` finite doubles (else ERR_NOT_FINITE).
///
/// # Safety
/// As [`in_array`].
pub(crate) unsafe fn in_slice<'a>(name: &str, p: *const f64, n: i64) -> Result<&'a [f64]> {
    let s = in_array(name, p, n)?;
    if let Some(i) = s.iter().position(|v| !v.is_finite()) {
        error::finite(&format!("{name}[{i}]"), s[i])?;
    }
    Ok(s)
}

/// A caller's output array of `n` values (doubles, or int64_t indices).
///
/// # Safety
/// `p` must be NULL or point to `n` writable `T`s.
pub(crate) unsafe fn out_slice<'a, T>(name: &str, p: *mut T, n: i64) -> Result<&'a mut [T]> {
    if p.is_null() {
        return Err(null_error(name));
    }
    Ok(std::slice::from_raw_parts_mut(p, n as usize))
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
    error::dimension(ld_name, ld, rows as i64, i64::MAX / 64)?;
    let len = ld as usize * cols.saturating_sub(1) + rows;
    let out = out_slice(name, ptr, len as i64)?;
    let ld = ld as usize;
    for j in 0..cols {
        out[j * ld..j * ld + rows].copy_from_slice(&column_major[j * rows..(j + 1) * rows]);
    }
    Ok(())
}

/// The shape of a caller's node-position array xyz[k + ld·i] (k < 3,
/// i < nodes): ld ≥ 3, `nodes` the object's node count, and its size
/// ld·(nodes − 1) + 3 representable.
pub(crate) fn check_nodes(ld: i64, nodes: i64, want: usize) -> Result<()> {
    error::dimension("ld", ld, 3, i64::MAX / 64)?;
    check_len("nodes", nodes, want as i64)?;
    // ld ≤ i64::MAX/64 times up to 2²⁰ nodes can overflow.
    ld.checked_mul(nodes - 1)
        .and_then(|v| v.checked_add(3))
        .ok_or_else(|| Error::new(Status::ErrOutOfRange, format!("argument `ld` ({ld}) times the nodes overflows")))?;
    Ok(())
}

/// Write node positions into `xyz` (leading dimension `ld`), after
/// [`check_nodes`].
///
/// # Safety
/// As [`write_matrix`] with 3 rows and one column per position.
pub(crate) unsafe fn write_positions(xyz: *mut f64, ld: i64, positions: &[[f64; 3]]) -> Result<()> {
    write_matrix("xyz", xyz, ld, "ld", 3, positions.len(), positions.as_flattened())
}

/// A `capacity` argument: a count ≥ 0.
pub(crate) fn capacity_arg(capacity: i64) -> Result<usize> {
    Ok(error::dimension("capacity", capacity, 0, i64::MAX)? as usize)
}

/// The size-query/copy-out pattern: `*count` receives the number of
/// `items`; the first min(capacity, items) are converted into `out` (which
/// may be NULL when that is 0: capacity 0 is a size query). Fewer than all:
/// RODKIT_STATUS_INFO_TRUNCATED.
///
/// # Safety
/// `count` must be NULL or writable; `out` NULL or `capacity` writable `T`s.
pub(crate) unsafe fn copy_out<S, T: Copy>(
    name: &str,
    out: *mut T,
    capacity: i64,
    count: *mut i64,
    items: &[S],
    mut convert: impl FnMut(&S) -> T,
) -> Result<Status> {
    let capacity = capacity_arg(capacity)?;
    *arg_mut("count", count)? = items.len() as i64;
    let k = items.len().min(capacity);
    if k > 0 {
        if out.is_null() {
            return Err(null_error(name));
        }
        for (i, item) in items[..k].iter().enumerate() {
            out.add(i).write(convert(item));
        }
    }
    Ok(if k < items.len() { Status::InfoTruncated } else { Status::Ok })
}

/// Set a handle out-parameter to NULL when there is one, so that it is NULL
/// on every failure (a NULL `out` is reported later, where it is needed).
///
/// # Safety
/// `out` must be NULL or writable.
pub(crate) unsafe fn clear_handle<T>(out: *mut *mut T) {
    if let Some(o) = out.as_mut() {
        *o = std::ptr::null_mut();
    }
}

/// Free a handle (a `Box` handed to C; NULL is accepted).
///
/// # Safety
/// `handle` must be NULL or a live handle of this type, not used afterwards.
pub(crate) unsafe fn free_handle<T>(handle: *mut T) {
    if !handle.is_null() {
        drop(Box::from_raw(handle));
    }
}

/// A NUL-terminated path from C (bytes as the system takes them).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string.
pub(super) unsafe fn path_arg(path: *const c_char) -> Result<PathBuf> {
    if path.is_null() {
        return Err(Error::new(Status::ErrNullPointer, "argument `path` is NULL"));
    }
    let bytes = CStr::from_ptr(path).to_bytes();
    if bytes.is_empty() {
        return Err(Error::new(Status::ErrOutOfRange, "argument `path` is empty"));
    }
    #[cfg(unix)]
    let path = {
        use std::os::unix::ffi::OsStrExt;
        PathBuf::from(std::ffi::OsStr::from_bytes(bytes))
    };
    #[cfg(not(unix))]
    let path = PathBuf::from(
        std::str::from_utf8(bytes).map_err(|_| Error::new(Status::ErrOutOfRange, "argument `path` is not UTF-8"))?,
    );
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[repr(i32)]
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Two {
        A = 1,
        B = 2,
    }
    c_enum!(Two, "a Two 1…2", [Two::A, Two::B]);

    /// References: the messages and statuses the C functions documented
    /// before this module existed (one each, written out).
    #[test]
    fn flags_and_enums_name_the_argument() {
        assert_eq!((flag("f", 0), flag("f", 1)), (Ok(false), Ok(true)));
        let e = flag("spec.kirchhoff", 2).unwrap_err();
        assert_eq!(
            (e.status, e.message.as_str()),
            (Status::ErrOutOfRange, "argument `spec.kirchhoff` out of range: must be 0 or 1 (got 2)")
        );
        assert_eq!(enum_arg::<Two>("t", 2), Ok(Two::B));
        assert_eq!(
            enum_arg::<Two>("t", 3).unwrap_err().message,
            "argument `t` out of range: must be a Two 1…2 (got 3)"
        );
        assert_eq!(
            non_negative("kappa", -0.5).unwrap_err().message,
            "argument `kappa` out of range: must be ≥ 0 (got -5e-1)"
        );
    }

    /// The size query, a truncated copy and a full one, by hand: 3 items.
    #[test]
    fn copy_out_queries_truncates_and_copies() {
        let items = [1.0, 2.0, 3.0];
        let mut count = -1i64;
        let query = unsafe { copy_out("out", std::ptr::null_mut::<f64>(), 0, &mut count, &items, |v| *v) };
        assert_eq!((query, count), (Ok(Status::InfoTruncated), 3));
        let mut out = [0.0; 2];
        let part = unsafe { copy_out("out", out.as_mut_ptr(), 2, &mut count, &items, |v| 10.0 * v) };
        assert_eq!((part, out), (Ok(Status::InfoTruncated), [10.0, 20.0]));
        let mut out = [0.0; 4];
        let all = unsafe { copy_out("out", out.as_mut_ptr(), 4, &mut count, &items, |v| *v) };
        assert_eq!((all, out), (Ok(Status::Ok), [1.0, 2.0, 3.0, 0.0]));
        let null = unsafe { copy_out("out", std::ptr::null_mut::<f64>(), 1, &mut count, &items, |v| *v) };
        assert_eq!(null.unwrap_err().status, Status::ErrNullPointer);
    }

    /// Two positions with ld = 4: xyz[k + 4i], the padding untouched; an ld
    /// whose product with the nodes overflows is refused.
    #[test]
    fn positions_go_to_their_leading_dimension() {
        let mut xyz = [-1.0; 7];
        check_nodes(4, 2, 2).unwrap();
        unsafe { write_positions(xyz.as_mut_ptr(), 4, &[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]) }.unwrap();
        assert_eq!(xyz, [1.0, 2.0, 3.0, -1.0, 4.0, 5.0, 6.0]);
        assert_eq!(check_nodes(2, 2, 2).unwrap_err().status, Status::ErrInvalidDimension);
        assert_eq!(check_nodes(4, 3, 2).unwrap_err().message, "argument `nodes` must be 2 (got 3)");
        let e = check_nodes(i64::MAX / 64, 1 << 20, 1 << 20).unwrap_err();
        assert!(e.message.contains("times the nodes overflows"), "{}", e.message);
    }
}
