//! The typed failures of the library (spec/00-overview.md, 0.3 "Failure").

use std::fmt;

/// The message of [`Error::over_budget`].
pub const OVER_BUDGET: &str = "not certified within the budget (the deadline passed)";

/// The message of [`Error::over_work`].
pub const OVER_WORK: &str = "not certified within the budget (the work limit was reached)";

/// Why a request was not answered. `Input` maps to exit status 2, `Uncertified` and
/// `Internal` to 3.
///
/// ```
/// use dalembert::{AnyScene, Error, FlowOptions, Model, Reason};
/// let model = Model::new(&AnyScene::new("knife", &[]).unwrap()).unwrap();
/// // a step budget of 3 cannot reach t = 600
/// let opts = FlowOptions { max_steps: 3, ..FlowOptions::default() };
/// match dalembert::flow(&model, &[0.0; 3], &[0.8, 0.8], 600.0, &opts) {
///     Err(Error::Uncertified(r)) => {
///         assert_eq!(r.reason, Reason::Budget);
///         assert!(r.reached.is_some_and(|t| t > 0.0 && t < 600.0));
///     }
///     other => panic!("{other:?}"),
/// }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// The request is malformed: unknown scene or parameter, wrong dimension, non-finite
    /// number, negative time, ...
    Input(String),
    /// The request is well formed but no enclosure could be proved; nothing is returned.
    Uncertified(Refusal),
    /// A fault of this crate, not of the request and not a failed proof (a bug to report);
    /// nothing is returned. Exit status 3, like every answer that certifies nothing.
    Internal(String),
}

/// A proof that was not completed: why, in words and as a kind a program can match, and
/// how far a flow had got.
#[derive(Clone, Debug, PartialEq)]
pub struct Refusal {
    /// The kind of refusal, for a program to match (spec 0.3).
    pub reason: Reason,
    /// What was not proved, in words (printed after `could not certify:`).
    pub message: String,
    /// For a validated flow: the time up to which the enclosure had been proved when the
    /// work stopped (`None` when no flow was under way, or it had not started).
    pub reached: Option<f64>,
}

/// The kind of a [`Refusal`] (spec 0.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Reason {
    /// A budget was spent: the deadline passed ([`crate::FlowOptions::deadline`]), the
    /// work limit was reached ([`crate::FlowOptions::work_limit`]), or more
    /// steps than [`crate::FlowOptions::max_steps`] (or the retraction's Newton work)
    /// would be needed. A larger budget may answer.
    Budget,
    /// The proof failed: no a priori enclosure even for tiny steps, a Krawczyk test or a
    /// Newton iteration that did not succeed, a singular Jacobian, an undecided comparison.
    NoProof,
    /// An enclosure became unbounded or not finite.
    Unbounded,
    /// The scene's data are not proved defined or regular where the query needs them (a
    /// divisor enclosing 0, a basis of D not proved of full rank).
    Undefined,
}

impl Reason {
    /// The name used in the batch protocol's error object (`"reason"`, contract E10).
    pub fn name(self) -> &'static str {
        match self {
            Reason::Budget => "budget",
            Reason::NoProof => "no_proof",
            Reason::Unbounded => "unbounded",
            Reason::Undefined => "undefined",
        }
    }
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl Error {
    /// An input error ([`Error::Input`], exit 2): the request is malformed.
    pub fn input(msg: impl Into<String>) -> Self {
        Error::Input(msg.into())
    }
    /// A failed proof ([`Reason::NoProof`]).
    pub fn uncertified(msg: impl Into<String>) -> Self {
        Error::refused(Reason::NoProof, msg)
    }
    /// A refusal of the given kind.
    pub fn refused(reason: Reason, msg: impl Into<String>) -> Self {
        Error::Uncertified(Refusal {
            reason,
            message: msg.into(),
            reached: None,
        })
    }
    /// A fault of the crate itself ([`Error::Internal`], exit 3): an invariant of the code
    /// that did not hold.
    pub fn internal(msg: impl Into<String>) -> Self {
        Error::Internal(msg.into())
    }
    /// The refusal of work that ran past its time budget (exit 3, [`Reason::Budget`]). Its
    /// message starts with `not certified within the budget`.
    pub fn over_budget() -> Self {
        Error::refused(Reason::Budget, OVER_BUDGET)
    }
    /// The refusal of work that reached its work limit (exit 3, [`Reason::Budget`],
    /// [`crate::FlowOptions::work_limit`]). Its message starts with `not certified within
    /// the budget`.
    pub fn over_work() -> Self {
        Error::refused(Reason::Budget, OVER_WORK)
    }
    /// `Err(over_budget())` once `deadline` has passed; `Ok` when there is none.
    pub fn check_deadline(deadline: Option<std::time::Instant>) -> Result<(), Error> {
        match deadline {
            Some(d) if std::time::Instant::now() >= d => Err(Error::over_budget()),
            _ => Ok(()),
        }
    }
    /// The same error, a refusal recording that a flow had been proved up to time `t`.
    pub fn reached(self, t: f64) -> Self {
        match self {
            Error::Uncertified(r) => Error::Uncertified(Refusal {
                reached: Some(t),
                ..r
            }),
            other => other,
        }
    }
    /// The kind of a refusal; `None` for input errors and internal faults.
    pub fn reason(&self) -> Option<Reason> {
        match self {
            Error::Uncertified(r) => Some(r.reason),
            _ => None,
        }
    }
    /// Whether a budget was spent ([`Reason::Budget`]): the request may succeed with more.
    pub fn is_budget(&self) -> bool {
        self.reason() == Some(Reason::Budget)
    }
    /// The command line's exit status for this error.
    pub fn code(&self) -> i32 {
        match self {
            Error::Input(_) => 2,
            Error::Uncertified(_) | Error::Internal(_) => 3,
        }
    }
    /// The message alone, without the prefix that `Display` adds.
    pub fn message(&self) -> &str {
        match self {
            Error::Input(m) | Error::Internal(m) => m,
            Error::Uncertified(r) => &r.message,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Input(m) => write!(f, "invalid input: {m}"),
            Error::Uncertified(r) => write!(f, "could not certify: {}", r.message),
            Error::Internal(m) => write!(f, "internal error (a bug of dalembert): {m}"),
        }
    }
}

impl std::error::Error for Error {}
