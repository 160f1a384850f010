//! Status codes: the one list from which the C enum `RodkitStatus` (by cbindgen)
//! and the messages of `rodkit_status_string` (by `build.rs`, from the doc
//! comment of each variant) are both generated.
//!
//! Convention (SUNDIALS-like, `../shared/spec/c-api.md`): `0` success, `> 0`
//! success with information, `< 0` failure, so `if (st < 0)` catches every
//! failure. Codes are part of the ABI: never renumber a shipped code, only add.
//!
//! Format rule for `build.rs`: each variant is preceded by exactly one `///`
//! line (its message) and written `Name = value,` on one line.

/// Status returned by every fallible rodkit function (as `int32_t`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// success
    Ok = 0,
    /// success, but the output was truncated to fit the caller's buffer
    InfoTruncated = 1,
    /// stopped early at the request of the progress callback (results so far are valid)
    InfoCancelled = 2,
    /// the continuation stopped at its step limit before reaching its target (the branch so far is valid)
    InfoStepLimit = 3,
    /// the continuation left the allowed parameter range before reaching its target (the branch so far is valid)
    InfoLambdaRange = 4,
    /// the continuation step fell below its minimum: the branch could not be followed further (the branch so far is valid)
    InfoStepTooSmall = 5,
    /// the continuation stopped where non-neighbouring parts of the rod came closer than its diameter (strands would cross; the branch up to there is valid)
    InfoStrandCrossing = 6,
    /// the computation failed partway and kept its results up to the last good point (the handle's failure report gives the error and its message)
    InfoFailedPartway = 7,
    /// the branch is complete, but a monitored function changed sign where no bifurcation accounting for it was located (the branch's unresolved brackets say where)
    InfoUnresolvedBifurcation = 8,
    /// internal error (a bug in rodkit: a panic was caught at the C boundary)
    ErrInternal = -1,
    /// a required pointer argument is NULL
    ErrNullPointer = -2,
    /// a numeric argument is NaN or infinite
    ErrNotFinite = -3,
    /// a numeric argument that must be positive is zero or negative
    ErrNotPositive = -4,
    /// a numeric argument is outside its allowed range
    ErrOutOfRange = -5,
    /// the material constants do not give a positive-definite stiffness
    ErrNotPositiveDefinite = -6,
    /// the geometry is impossible (inverted or degenerate sizes)
    ErrInvalidGeometry = -7,
    /// an array's length or leading dimension is inconsistent with the problem
    ErrInvalidDimension = -8,
    /// an iterative solver did not converge to the requested tolerance
    ErrNotConverged = -9,
    /// a computed result is not finite (overflow or an ill-posed problem)
    ErrNonFiniteResult = -10,
    /// the material lost stability at the requested state (e.g. Saint Venant-Kirchhoff in strong compression)
    ErrMaterialInstability = -11,
    /// the call would exceed its work bound (the message gives the estimated cost and the bound); nothing was computed
    ErrWorkLimit = -12,
    /// the requested tolerance is below what the model or floating-point round-off can reach (the message gives the best reachable)
    ErrToleranceUnreachable = -13,
    /// a file could not be written (the message names the path and the system's reason)
    ErrIo = -14,
}

include!(concat!(env!("OUT_DIR"), "/status_messages.rs"));

impl Status {
    /// Every status, in declaration order (generated from the list above).
    pub const ALL: &'static [Status] = STATUS_ALL;

    /// The integer code as it crosses the C ABI.
    pub const fn code(self) -> i32 {
        self as i32
    }

    /// The status with this code, if any.
    pub fn from_code(code: i32) -> Option<Status> {
        Self::ALL.iter().copied().find(|s| s.code() == code)
    }

    /// Short human-readable description (the variant's doc comment).
    pub fn message(self) -> &'static str {
        let m = status_message_nul(self);
        &m[..m.len() - 1]
    }

    /// The description with a trailing NUL, for `rodkit_status_string`.
    pub fn message_nul(self) -> &'static str {
        status_message_nul(self)
    }

    /// `true` for failures (negative codes).
    pub const fn is_failure(self) -> bool {
        (self as i32) < 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn codes_are_unique_and_signed_by_kind() {
        // Reference: the convention of c-api.md (0 ok, > 0 info, < 0 failure),
        // encoded in the variant names.
        let mut seen = HashSet::new();
        for s in Status::ALL {
            assert!(seen.insert(s.code()), "duplicate code {}", s.code());
            let name = format!("{s:?}");
            if name.starts_with("Err") {
                assert!(s.code() < 0, "{name}");
            } else if name.starts_with("Info") {
                assert!(s.code() > 0, "{name}");
            } else {
                assert_eq!(name, "Ok");
                assert_eq!(s.code(), 0);
            }
            assert!(!s.message().is_empty() && !s.message().contains('\0'));
            assert_eq!(Status::from_code(s.code()), Some(*s));
        }
        assert_eq!(Status::ALL.len(), 23);
        assert_eq!(Status::from_code(-999), None);
    }
}
