#![cfg(feature = "sundials")]
#[path = "support/sundials.rs"]
mod sundials;
