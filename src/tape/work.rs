//! The work meter: a count of the coefficient terms this thread's Taylor series computed, a
//! measure of work that replays the same on every machine ([spec (5.8''')](crate::spec::enclosure)).

use std::cell::Cell;

thread_local! {
    static WORK: Cell<u64> = const { Cell::new(0) };
}

/// The arithmetic work this thread has done in Taylor series so far ([spec (5.8''')](crate::spec::enclosure)): every
/// series of order `p` on a tape of `L` operations (`Tape::ode_taylor`) adds
/// `L (p + 1) (p + 2) / 2`, the number of coefficient terms a tape of products computes. A
/// measure of work that replays the same on every machine;
/// [`crate::FlowOptions::work_limit`] is stated in it.
pub fn work_done() -> u64 {
    WORK.with(Cell::get)
}

/// Adds `terms` to this thread's work.
pub(super) fn charge(terms: u64) {
    WORK.with(|w| w.set(w.get().saturating_add(terms)));
}

/// `L (p + 1) (p + 2) / 2`.
pub(super) fn terms(ops: usize, order: usize) -> u64 {
    let order = order as u64;
    let per_op = order.saturating_add(1).saturating_mul(order.saturating_add(2)) / 2;
    (ops as u64).saturating_mul(per_op)
}
