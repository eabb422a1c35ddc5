//! Interval scalars beyond binary64 ([spec chapter 12](crate::spec::precision)).
//!
//! - [`dd`]: double-double numbers [`dd::Dd`] and outward-rounded intervals
//!   [`dd::DdInterval`] (about 106 bits), with rigorous elementary functions.

pub mod dd;
mod dd_big;
mod dd_elementary;
