//! Interval scalars beyond the 53 bits of inari's `Interval`: [spec chapter 12](crate::spec::precision).
//!
//! - [`mp`]: [`MpInterval`](mp::MpInterval), intervals with ends of any number of bits
//!   chosen at run time (arbitrary precision, pure Rust), with the elementary functions.

pub mod mp;
mod mp_elem;
pub mod mp_float;
