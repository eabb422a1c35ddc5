//! The settings of the validated integrator and what it reports ([spec eqs. (5.8)](crate::spec::enclosure),
//! (5.10), (5.13)).

use super::ival::Ival;
use crate::progress::Progress;
use crate::Error;

/// Settings of the validated integrator: `FlowOptions::default()` and the `with_*` setters,
/// e.g. `FlowOptions::default().with_order(28).with_max_taylor_steps(500)`. `#[non_exhaustive]`:
/// settings may be added; build them with the setters (or assign fields of a default).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct FlowOptions {
    /// Taylor order `p` of the steps. `None` (default): `p = 22` (`DEFAULT_ORDER`), or 28
    /// for a span of two or three steps ([spec (5.8)](crate::spec::enclosure) (e)), and a step that reaches the end
    /// may take a lower order that also reaches it ([spec eqs. (5.8)](crate::spec::enclosure), (5.8')); `Some(p)`:
    /// `p` for every step (`Some(0)` is taken as `None`).
    pub order: Option<usize>,
    /// Refuse ([`crate::Reason::Budget`], [`crate::Limit::TaylorSteps`]) rather than take
    /// more accepted steps of the validated Taylor integrator than this (default 20000).
    pub max_taylor_steps: usize,
    /// `None` (default): step sizes chosen by [spec eq. (5.8)](crate::spec::enclosure). `Some(h)`, `h > 0`: every step
    /// tries the size `h` (rounded down to three significant bits) without the width
    /// tolerances of (5.8); a step whose a priori enclosure fails is retried smaller as in
    /// (5.8) ([spec eq. (5.13)](crate::spec::enclosure)). `Some(h)` with `h` not > 0 is taken as `None`.
    pub fixed_h: Option<f64>,
    /// Told `("flow", reached, t)` after each accepted step (for a progress display; it
    /// sees nothing else and cannot change the result). Silent by default.
    pub progress: Progress,
    /// Refuse with [`Error::over_budget`] (exit 3) once this instant has passed: checked
    /// before every step of the validated flow and every float flow of the retraction's
    /// Newton guess. `None`: no time limit (the step counts still bound the work).
    pub deadline: Option<std::time::Instant>,
    /// Refuse with [`Error::over_work`] (exit 3, [`crate::Reason::Budget`]) once
    /// [`crate::work_done`] on this thread has reached this count: checked where the
    /// deadline is, and before every try of a step. [`FlowOptions::allow_work`]`(W)` sets it
    /// for a call that may do the work `W` ([spec (5.8''')](crate::spec::enclosure)); unlike a deadline it replays the
    /// same on every machine. `None` (default): no work limit.
    pub work_limit: Option<u64>,
    /// How the basis of the set is renewed at each step ([spec eq. (5.10)](crate::spec::enclosure)).
    pub basis: Basis,
    /// `true` (default): the set is a doubleton whose step errors are folded into its
    /// propagated part once they are 10 times wider ([spec (5.10')](crate::spec::enclosure)). `false`: they never
    /// are, and a point's flow is the single parallelepiped `m + B r` of the previous
    /// version (for comparisons; on knife-eps at T = 600 it is 2.3 times wider).
    pub reorganise: bool,
    /// (12.0.9) The series over a priori boxes tried in f64 by (5.5''') whatever the
    /// precision (the retraction's flows and the exact step's second flow at 106 bits).
    pub(crate) box_series_in_f64: bool,
    /// (12.0.10) The level the state is held to when it is above the precision's own
    /// ([`Ival::eps`]): the step rule (5.8), the remainder's tolerance and the orders aim at
    /// it (the first Krawczyk test of the retraction at 106 bits). `None`: the precision's.
    pub(crate) level: Option<f64>,
}

/// The basis `B'` of the next set in Lohner's update ([spec eq. (5.10)](crate::spec::enclosure)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Basis {
    /// `B' = mid([J] B)`, the propagated parallelepiped (its inverse proved by (5.9); the
    /// orthogonal basis when that fails). The default: on the knife at T = 600 it is 94
    /// times narrower than the orthogonal one.
    #[default]
    Parallelepiped,
    /// `B'` = the orthogonal factor of a QR factorisation of `mid([J] B)` (Lohner's).
    Orthogonal,
}

impl FlowOptions {
    /// With the Taylor order `p` for every step ([`FlowOptions::order`]).
    pub fn with_order(mut self, p: usize) -> Self {
        self.order = Some(p);
        self
    }
    /// With at most `n` accepted Taylor steps ([`FlowOptions::max_taylor_steps`]).
    pub fn with_max_taylor_steps(mut self, n: usize) -> Self {
        self.max_taylor_steps = n;
        self
    }
    /// With every step trying the size `h` ([`FlowOptions::fixed_h`]).
    pub fn with_fixed_h(mut self, h: f64) -> Self {
        self.fixed_h = Some(h);
        self
    }
    /// With `progress` told of each accepted step ([`FlowOptions::progress`]).
    pub fn with_progress(mut self, progress: Progress) -> Self {
        self.progress = progress;
        self
    }
    /// With the deadline `d` ([`FlowOptions::deadline`]; `None`: no time limit).
    pub fn with_deadline(mut self, d: Option<std::time::Instant>) -> Self {
        self.deadline = d;
        self
    }
    /// With the work limit `w` ([`FlowOptions::work_limit`]; `None`: no work limit). See
    /// also [`FlowOptions::allow_work`].
    pub fn with_work_limit(mut self, w: Option<u64>) -> Self {
        self.work_limit = w;
        self
    }
    /// With the basis renewal `basis` ([`FlowOptions::basis`]).
    pub fn with_basis(mut self, basis: Basis) -> Self {
        self.basis = basis;
        self
    }
    /// With the doubleton's reorganisation on or off ([`FlowOptions::reorganise`]).
    pub fn with_reorganise(mut self, on: bool) -> Self {
        self.reorganise = on;
        self
    }

    /// The Taylor order given, `None` when it is to be chosen ([spec (5.8)](crate::spec::enclosure)).
    pub(crate) fn given_order(&self) -> Option<usize> {
        self.order.filter(|&p| p > 0)
    }

    /// The level the flow holds its state to ([`FlowOptions::level`], at least `I::eps()`).
    pub(crate) fn level<I: Ival>(&self) -> f64 {
        self.level.map_or(I::eps(), |l| l.max(I::eps()))
    }

    /// `q`, one of `I`'s orders, scaled to the level (12.0.10): by the ratio of the bits of
    /// [`FlowOptions::level`] to those of `I::eps()`, so that a series of the order aims at
    /// the level as the type's order aims at its rounding; `q` itself at `I`'s own level.
    pub(crate) fn order_at_level<I: Ival>(&self, q: usize) -> usize {
        let (level, own) = (self.level::<I>(), I::eps());
        if level <= own {
            return q;
        }
        ((q as f64 * level.log2() / own.log2()).ceil() as usize).clamp(1, q)
    }

    /// The step size every step tries, `None` when (5.8) chooses them.
    pub(crate) fn given_h(&self) -> Option<f64> {
        self.fixed_h.filter(|&h| h > 0.0)
    }

    /// These options with the work `w` allowed from now ([spec (5.8''')](crate::spec::enclosure)): `work_limit`
    /// becomes [`crate::work_done`]` + w`, or stays where it is if that is lower.
    pub fn allow_work(mut self, w: u64) -> Self {
        let limit = crate::tape::work_done().saturating_add(w);
        self.work_limit = Some(self.work_limit.map_or(limit, |l| l.min(limit)));
        self
    }

    /// `Err` ([`Reason::Budget`](crate::Reason::Budget)) once the deadline has passed or
    /// the work limit is reached; `Ok` otherwise.
    pub fn check_budget(&self) -> Result<(), Error> {
        Error::check_deadline(self.deadline)?;
        match self.work_limit {
            Some(w) if crate::tape::work_done() >= w => Err(Error::over_work()),
            _ => Ok(()),
        }
    }
}

impl Default for FlowOptions {
    fn default() -> Self {
        FlowOptions {
            order: None,
            max_taylor_steps: 20_000,
            fixed_h: None,
            progress: Progress::default(),
            deadline: None,
            work_limit: None,
            basis: Basis::Parallelepiped,
            reorganise: true,
            box_series_in_f64: false,
            level: None,
        }
    }
}

/// What the integrator did.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(not(feature = "internals"), non_exhaustive)]
pub struct FlowStats {
    /// The Taylor order `p` of the steps (a last step may have used a lower one, [spec (5.8')](crate::spec::enclosure)).
    pub order: usize,
    /// Accepted steps.
    pub steps: usize,
    /// Steps tried and rejected (a priori enclosure or remainder not good enough).
    pub rejected: usize,
    /// The smallest accepted step (the lower end of an interval last step); 0 when no step
    /// was taken.
    pub h_min: f64,
    /// The largest accepted step (the upper end of an interval last step).
    pub h_max: f64,
}
