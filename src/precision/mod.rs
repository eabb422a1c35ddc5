//! Interval scalars beyond the 53 bits of inari's `Interval` ([spec chapter 12](crate::spec::precision)).
//!
//! - [`dd`]: double-double numbers [`dd::Dd`] and outward-rounded intervals
//!   [`dd::DdInterval`] (about 106 bits), with rigorous elementary functions.
//! - [`mp`]: [`MpInterval`](mp::MpInterval), intervals with ends of a number of bits chosen
//!   at run time (up to [`mp_float::MAX_PREC`]), `Copy`, with the elementary functions; the
//!   ends are [`mp_float::Mp`] numbers whose significands are fixed arrays of 64-bit limbs
//!   (`limbs`: no heap in any arithmetic operation; `mp_decimal`: decimal input and output).
//! - [`wide`]: [`WideInterval`](wide::WideInterval), the same sets at the precision in force
//!   on the thread (107 to 1,024 bits), which the validated integrator computes with above
//!   106 bits.

pub mod dd;
mod dd_big;
mod dd_elementary;
mod limbs;
pub mod mp;
mod mp_decimal;
mod mp_dot;
mod mp_elem;
pub mod mp_float;
pub mod wide;
