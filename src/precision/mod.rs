//! Interval scalars beyond the 53 bits of inari's `Interval` ([spec chapter 12](crate::spec::precision)).
//!
//! - [`dd`]: double-double numbers [`dd::Dd`] and outward-rounded intervals
//!   [`dd::DdInterval`] (about 106 bits), with rigorous elementary functions.
//! - [`mp`]: [`MpInterval`](mp::MpInterval), intervals with ends of any number of bits
//!   chosen at run time (arbitrary precision, pure Rust), with the elementary functions.
//! - [`wide`]: [`WideInterval`](wide::WideInterval), the same sets with `Copy` ends of up to
//!   512 bits, which the validated integrator computes with above 106 bits.

pub mod dd;
mod dd_big;
mod dd_elementary;
pub mod mp;
mod mp_elem;
pub mod mp_float;
pub mod wide;
