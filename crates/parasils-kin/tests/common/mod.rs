//! What the integration tests of this crate share: a smooth stand-in for
//! the paper's reorientation ([`motion`]) and module 1's check values and
//! test robots ([`module1`]).
//!
//! Each test file declares `mod common;` and uses the parts it needs.

pub mod module1;
pub mod motion;
