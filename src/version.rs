//! Library and ABI versions. The library version comes from Cargo.toml (one
//! source: `build.rs` writes the same numbers into the header's
//! `RODKIT_VERSION_*` macros). The ABI version changes only when the binary
//! interface does (a signature, a struct layout or an enum value).

/// Bump when the binary interface changes incompatibly. The header's
/// `RODKIT_ABI_VERSION` is written from this constant by `build.rs`.
pub const ABI_VERSION: i32 = 3;

const fn parse(s: &str) -> i32 {
    let b = s.as_bytes();
    let mut i = 0;
    let mut v = 0i32;
    while i < b.len() {
        v = v * 10 + (b[i] - b'0') as i32;
        i += 1;
    }
    v
}

pub const MAJOR: i32 = parse(env!("CARGO_PKG_VERSION_MAJOR"));
pub const MINOR: i32 = parse(env!("CARGO_PKG_VERSION_MINOR"));
pub const PATCH: i32 = parse(env!("CARGO_PKG_VERSION_PATCH"));
