//! The error type of the Rust API and the argument checks shared by the Rust
//! API and the C boundary. Every message names the argument and its value, so
//! a C caller reading `rodkit_last_error_message()` knows what to fix.

use crate::status::Status;
use std::fmt;

/// A failure: a negative [`Status`] plus a message naming what went wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    pub status: Status,
    pub message: String,
}

/// Result type of the Rust API.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub fn new(status: Status, message: impl Into<String>) -> Self {
        debug_assert!(status.is_failure(), "Error built with non-failure {status:?}");
        Error { status, message: message.into() }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({:?}, {})", self.message, self.status, self.status.code())
    }
}

impl std::error::Error for Error {}

/// `value` must be finite.
pub fn finite(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::new(Status::ErrNotFinite, format!("argument `{name}` must be finite (got {value:e})")))
    }
}

/// `value` must be finite and > 0.
pub fn positive(name: &str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(Error::new(Status::ErrNotPositive, format!("argument `{name}` must be positive (got {value:e})")))
    }
}

/// `value` must be finite and in the closed interval [lo, hi].
pub fn in_range(name: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
    finite(name, value)?;
    if (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(Error::new(
            Status::ErrOutOfRange,
            format!("argument `{name}` out of range: must lie in [{lo:e}, {hi:e}] (got {value:e})"),
        ))
    }
}

/// An integer count, order or index must lie in [lo, hi] (ErrOutOfRange).
pub fn count_in_range(name: &str, value: i64, lo: i64, hi: i64) -> Result<i64> {
    if (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(Error::new(
            Status::ErrOutOfRange,
            format!("argument `{name}` out of range: must lie in [{lo}, {hi}] (got {value})"),
        ))
    }
}

/// An array's length, capacity or leading dimension must lie in [lo, hi]
/// (ErrInvalidDimension: the array does not fit the problem).
pub fn dimension(name: &str, value: i64, lo: i64, hi: i64) -> Result<i64> {
    if (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        let want = if lo == hi { format!("{lo}") } else { format!("in [{lo}, {hi}]") };
        Err(Error::new(
            Status::ErrInvalidDimension,
            format!("argument `{name}` must be {want} (got {value}): the array does not fit the problem"),
        ))
    }
}

/// Every entry of a computed result must be finite: NaN never leaves rodkit.
pub fn finite_result(what: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::new(
            Status::ErrNonFiniteResult,
            format!("{what}: entry {i} is not finite ({:e}); the inputs are out of the representable range", values[i]),
        )),
    }
}

/// "eigenvalues from λ_min to λ_max" of a symmetric matrix: what a message
/// about a stiffness that is not positive definite says instead of printing
/// the matrix (the caller has it; printed, it made 1–5 kB messages).
pub fn eigen_range(eigenvalues: &[f64]) -> String {
    let lo = eigenvalues.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = eigenvalues.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    format!("eigenvalues from {lo:.3e} to {hi:.3e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_argument_and_value() {
        let e = positive("thickness", -0.25).unwrap_err();
        assert_eq!(e.status, Status::ErrNotPositive);
        assert!(e.message.contains("`thickness`") && e.message.contains("-2.5e-1"), "{}", e.message);

        let e = positive("e2", f64::NAN).unwrap_err();
        assert_eq!(e.status, Status::ErrNotFinite);
        assert!(e.message.contains("`e2`") && e.message.contains("NaN"), "{}", e.message);

        let e = in_range("nu12", 3.0, -1.0, 1.0).unwrap_err();
        assert_eq!(e.status, Status::ErrOutOfRange);
        assert!(e.message.contains("`nu12`") && e.message.contains("3e0"), "{}", e.message);

        let e = dimension("ldk", 2, 3, i64::MAX).unwrap_err();
        assert_eq!(e.status, Status::ErrInvalidDimension);
        assert!(e.message.contains("`ldk`") && e.message.contains("got 2"));

        assert_eq!(positive("x", 2.0), Ok(2.0));
        assert_eq!(in_range("x", 1.0, -1.0, 1.0), Ok(1.0));
        assert!(finite_result("k", &[1.0, f64::INFINITY]).is_err());
        assert_eq!(eigen_range(&[2.0, -0.5, 1e300]), "eigenvalues from -5.000e-1 to 1.000e300");
    }
}
