//! Version queries. The header's RODKIT_VERSION_* and RODKIT_ABI_VERSION
//! macros come from the same sources (Cargo.toml, src/version.rs): compare
//! them with these at run time to detect a header/library mismatch.

use super::args::arg_mut;
use super::{guard, guard_value};
use crate::status::Status;
use crate::version;

/// Library version (semantic versioning, from Cargo.toml). All three pointers
/// are required; on failure nothing is written.
#[no_mangle]
pub unsafe extern "C" fn rodkit_version(major: *mut i32, minor: *mut i32, patch: *mut i32) -> i32 {
    guard(|| {
        let major = arg_mut("major", major)?;
        let minor = arg_mut("minor", minor)?;
        let patch = arg_mut("patch", patch)?;
        (*major, *minor, *patch) = (version::MAJOR, version::MINOR, version::PATCH);
        Ok(Status::Ok)
    })
}

/// ABI version of the loaded library; equals RODKIT_ABI_VERSION of the
/// header it was built with. It changes only when the binary interface does.
/// cbindgen:fortran-result=version
#[no_mangle]
pub extern "C" fn rodkit_library_abi_version() -> i32 {
    guard_value(-1, || version::ABI_VERSION)
}
