//! The Taylor orders of the method ([spec eqs. (5.6)](crate::spec::enclosure), (5.8), (5.8')): the lowest layer of
//! the validated integrator, read by the interval types ([`super::ival::Ival`]) and the
//! step and order control.

/// The order used when none is given ([spec eq. (5.8)](crate::spec::enclosure): measured, fewer and longer steps than
/// the textbook -ln(2^-53)/2 pay, because each step also renews the set's basis).
pub const DEFAULT_ORDER: usize = 22;

/// (5.8) (e): the order of a span that takes at most `SHORT_REST` steps at DEFAULT_ORDER.
pub(super) const SHORT_ORDER: usize = 28;

/// The lower orders a last step may take instead of the flow's order ([spec (5.8')](crate::spec::enclosure)).
pub(super) const LOW_ORDERS: [usize; 5] = [6, 8, 10, 12, 15];

/// The orders tried for the Taylor series of the variational equation ([spec eq. (5.6)](crate::spec::enclosure)),
/// lowest first.
pub(super) const JAC_ORDERS: [usize; 6] = [3, 5, 8, 12, 16, 20];

/// The orders tried for the variational equation when the derivative is asked to the
/// rounding level ([spec eq. (5.6)](crate::spec::enclosure), Theorem 5.3), lowest first: [`JAC_ORDERS`] and, two
/// apart, the orders to four above the state's, so that a step the state's rule (5.8) sized
/// still meets the derivative's criterion (its remainder below 1 ulp of its size) instead of
/// falling back to the step over the whole set (5.6''), at the lowest of them that does (the
/// series grow from rung to rung: a rung that fails costs its test only).
pub(super) const PRECISE_JAC_ORDERS: [usize; 9] = [3, 5, 8, 12, 16, 20, 22, 24, 28];
