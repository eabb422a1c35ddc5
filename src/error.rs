//! The typed failures of the library ([spec/00-overview.md](crate::spec::overview), 0.3 "Failure").

use std::fmt;

/// The message of [`Error::over_budget`].
pub const OVER_BUDGET: &str = "not certified within the budget (the deadline passed)";

/// The message of [`Error::over_work`].
pub const OVER_WORK: &str = "not certified within the budget (the work limit was reached)";

/// Why a request was not answered ([spec 0.3](crate::spec::overview#03-failure) "Failure").
///
/// Each variant carries a struct with a message in words and a kind a program can match:
/// [`InputError::kind`] says which part of the request is at fault, [`Refusal::reason`]
/// (and [`Refusal::limit`]) why a proof was not completed, [`InternalError::invariant`]
/// which of the crate's own invariants failed. Decide on the kinds, never on the message
/// text. The enum and its structs are `#[non_exhaustive]`: variants, kinds and fields may
/// be added without a breaking release.
///
/// ```
/// use dalembert::{AnyScene, Error, FlowOptions, Limit, Model, Reason};
/// let model = Model::new(&AnyScene::new("knife", &[])?)?;
/// // a budget of 3 Taylor steps cannot reach t = 600
/// let opts = FlowOptions::default().with_max_taylor_steps(3);
/// match dalembert::flow(&model, &[0.0; 3], &[0.8, 0.8], 600.0, &opts) {
///     Err(Error::Uncertified(r)) => {
///         assert_eq!(r.reason, Reason::Budget);
///         assert_eq!(r.limit, Some(Limit::TaylorSteps));
///         assert!(r.reached.is_some_and(|t| t > 0.0 && t < 600.0));
///     }
///     other => panic!("{other:?}"),
/// }
/// # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The request is malformed: unknown scene or parameter, wrong dimension, non-finite
    /// number, negative time, ...
    Input(InputError),
    /// The request is well formed but no enclosure could be proved; nothing is returned.
    Uncertified(Refusal),
    /// A fault of this crate, not of the request and not a failed proof (a bug to report);
    /// nothing is returned.
    Internal(InternalError),
}

/// A malformed request: which part of it ([`InputKind`]) and what is wrong, in words.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct InputError {
    /// Which part of the request is at fault, for a program to match.
    pub kind: InputKind,
    /// What is wrong, in words (printed after `invalid input:`).
    pub message: String,
}

/// Which part of a request an [`InputError`] is about.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum InputKind {
    /// Not classified further: the message says what.
    Other,
    /// A key of a batch request, or an option of the command line: its name (`"h"`,
    /// `"q0"`, `"--tol"`).
    Key(String),
    /// One element of a list given under a key: the key and the 0-based index.
    Element {
        /// The key the list was given under.
        key: String,
        /// The element's 0-based index in the list.
        index: usize,
    },
    /// The scene: an unknown name, or a scene file or description that is malformed.
    Scene(String),
    /// A parameter of the scene: its name.
    Parameter(String),
    /// A vector with the wrong number of components.
    Dimension {
        /// What the vector is (`"q"`, `"u"`, `"q0"`).
        what: String,
        /// The number of components given.
        got: usize,
        /// The number of components the scene needs.
        expected: usize,
    },
    /// A number that is not finite (or not > 0, or out of range) where one is needed: what
    /// it is (`"t"`, `"h"`, `"state"`).
    Number(String),
    /// A row of a candidate trajectory (0-based `k` of `q_k`), and the column at fault
    /// when one is.
    Row {
        /// The row's index `k`.
        row: usize,
        /// The 0-based column, when one column is at fault.
        column: Option<usize>,
    },
    /// The times of a dense or non-uniform request (not increasing, not finite, a step
    /// that is not a float).
    Times,
    /// A user's stepper failed (testing kit): the step at which it did, when known.
    Stepper {
        /// The step `k` whose `q_{k+1}` was asked for, when it is known.
        step: Option<usize>,
    },
}

/// A fault of the crate: which invariant did not hold ([`Invariant`]) and, in words, where.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct InternalError {
    /// The invariant that did not hold.
    pub invariant: Invariant,
    /// Where and how, in words (printed after `internal error (a bug of dalembert):`).
    pub message: String,
}

/// The invariant of the crate an [`InternalError`] reports broken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Invariant {
    /// Not classified further: the message says what.
    Other,
    /// Two enclosures of the same exact quantity were disjoint (a self-check of the
    /// interval arithmetic or of a Krawczyk refinement).
    DisjointEnclosures,
    /// A value the code had just computed was missing (an empty answer, a lost point).
    Missing,
    /// A scene read a parameter it had not declared.
    UndeclaredParameter,
    /// The output of a running command closed before the answers were written.
    Output,
}

/// A proof that was not completed: why, in words and as a kind a program can match, and
/// how far a flow had got.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Refusal {
    /// The kind of refusal, for a program to match ([spec 0.3](crate::spec::overview#03-failure)).
    pub reason: Reason,
    /// For a [`Reason::Budget`] refusal: which budget was spent (`None` for the other
    /// reasons).
    pub limit: Option<Limit>,
    /// What was not proved, in words (printed after `could not certify:`).
    pub message: String,
    /// For a validated flow: the time up to which the enclosure had been proved when the
    /// work stopped (`None` when no flow was under way, or it had not started).
    pub reached: Option<f64>,
    /// What the refusal is about, one of a documented set ([`Cause`], contract E23, [spec
    /// 0.3](crate::spec::overview#03-failure)): finer than `reason`, and the set the steps
    /// shrank toward when a step limit was reached for that.
    pub cause: Cause,
}

/// What a [`Refusal`] is about (contract E23, [spec 0.3](crate::spec::overview#03-failure)):
/// one cause, one name, whatever path refused. Only words a refusal: nothing is proved or
/// answered with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Cause {
    /// The mass matrix is not proved positive definite where the query needs it.
    Mass,
    /// The derived basis of D is singular there (its pivot block, or the rank of the
    /// constraints and the basis).
    Basis,
    /// An expression of the scene is not proved finite or defined there (outside its domain).
    Domain,
    /// The enclosure grew too wide before any of the scene's data failed: a higher precision
    /// may answer.
    Width,
    /// The step limit was reached ([`crate::FlowOptions::max_taylor_steps`], `--max-steps`).
    Steps,
    /// The work budget was spent ([`crate::FlowOptions::work_limit`], `--work`).
    Work,
    /// The wall-clock deadline passed (`--deadline`).
    Deadline,
    /// A proof failed: a priori enclosure, Krawczyk, Newton, an undecided tolerance.
    Proof,
    /// An enclosure became unbounded or not finite.
    Unbounded,
}

impl Cause {
    /// The name in the batch protocol's error object (`"cause"`, contract E23).
    pub fn name(self) -> &'static str {
        match self {
            Cause::Mass => "mass",
            Cause::Basis => "basis",
            Cause::Domain => "domain",
            Cause::Width => "width",
            Cause::Steps => "steps",
            Cause::Work => "work",
            Cause::Deadline => "deadline",
            Cause::Proof => "proof",
            Cause::Unbounded => "unbounded",
        }
    }

    /// Every cause, in the order of the contract's table (E23).
    pub const ALL: [Cause; 9] = [
        Cause::Mass,
        Cause::Basis,
        Cause::Domain,
        Cause::Width,
        Cause::Steps,
        Cause::Work,
        Cause::Deadline,
        Cause::Proof,
        Cause::Unbounded,
    ];

    /// The cause a refusal has unless a more precise one is known: from its reason and,
    /// for a budget, the limit spent.
    fn of(reason: Reason, limit: Option<Limit>) -> Cause {
        match (reason, limit) {
            (Reason::Budget, Some(Limit::Deadline)) => Cause::Deadline,
            (Reason::Budget, Some(Limit::Work)) => Cause::Work,
            (Reason::Budget, _) => Cause::Steps,
            (Reason::NoProof, _) => Cause::Proof,
            (Reason::Unbounded, _) => Cause::Unbounded,
            (Reason::Undefined, _) => Cause::Domain,
        }
    }
}

/// Which budget a [`Reason::Budget`] refusal spent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Limit {
    /// The deadline passed ([`crate::FlowOptions::deadline`]).
    Deadline,
    /// The work limit was reached ([`crate::FlowOptions::work_limit`]).
    Work,
    /// More accepted steps of the validated Taylor integrator than
    /// [`crate::FlowOptions::max_taylor_steps`] would be needed.
    TaylorSteps,
    /// A retraction spent its work budget: the float Taylor steps of its Newton guess or
    /// the validated steps of its Krawczyk boxes' flows (each a multiple of
    /// [`crate::FlowOptions::max_taylor_steps`]).
    RetractionWork,
}

/// The kind of a [`Refusal`] ([spec 0.3](crate::spec::overview#03-failure)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Reason {
    /// A budget was spent: the deadline passed ([`crate::FlowOptions::deadline`]), the
    /// work limit was reached ([`crate::FlowOptions::work_limit`]), or more
    /// steps than [`crate::FlowOptions::max_taylor_steps`] (or the retraction's Newton
    /// work) would be needed; [`Refusal::limit`] says which. A larger budget may answer.
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

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl fmt::Display for InternalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Refusal {}
impl std::error::Error for InputError {}
impl std::error::Error for InternalError {}

impl Error {
    /// An input error ([`Error::Input`]) of kind [`InputKind::Other`]: the request is
    /// malformed.
    pub fn input(msg: impl Into<String>) -> Self {
        Error::input_at(InputKind::Other, msg)
    }
    /// An input error about the part `kind` of the request.
    pub fn input_at(kind: InputKind, msg: impl Into<String>) -> Self {
        Error::Input(InputError {
            kind,
            message: msg.into(),
        })
    }
    /// An input error about the value under the key or option `key`.
    pub fn input_key(key: &str, msg: impl Into<String>) -> Self {
        Error::input_at(InputKind::Key(key.to_string()), msg)
    }
    /// The same error, an input error now of kind `kind` (a reader that knows more about
    /// where the value came from than the parser it called); other errors unchanged.
    #[cfg(feature = "cli")]
    pub(crate) fn of_kind(self, kind: InputKind) -> Self {
        match self {
            Error::Input(e) => Error::Input(InputError { kind, ..e }),
            other => other,
        }
    }
    /// A failed proof ([`Reason::NoProof`]).
    pub fn uncertified(msg: impl Into<String>) -> Self {
        Error::refused(Reason::NoProof, msg)
    }
    /// A refusal of the given kind.
    pub fn refused(reason: Reason, msg: impl Into<String>) -> Self {
        Error::Uncertified(Refusal {
            reason,
            limit: None,
            message: msg.into(),
            reached: None,
            cause: Cause::of(reason, None),
        })
    }
    /// A [`Reason::Budget`] refusal that spent the budget `limit`.
    pub fn over_limit(limit: Limit, msg: impl Into<String>) -> Self {
        Error::Uncertified(Refusal {
            reason: Reason::Budget,
            limit: Some(limit),
            message: msg.into(),
            reached: None,
            cause: Cause::of(Reason::Budget, Some(limit)),
        })
    }
    /// A fault of the crate itself ([`Error::Internal`], [`Invariant::Other`]): an
    /// invariant of the code that did not hold.
    pub fn internal(msg: impl Into<String>) -> Self {
        Error::internal_at(Invariant::Other, msg)
    }
    /// A fault of the crate itself: the invariant `invariant` did not hold.
    pub fn internal_at(invariant: Invariant, msg: impl Into<String>) -> Self {
        Error::Internal(InternalError {
            invariant,
            message: msg.into(),
        })
    }
    /// The refusal of work that ran past its time budget ([`Reason::Budget`],
    /// [`Limit::Deadline`]). Its message starts with `not certified within the budget`.
    pub fn over_budget() -> Self {
        Error::over_limit(Limit::Deadline, OVER_BUDGET)
    }
    /// The refusal of work that reached its work limit ([`Reason::Budget`], [`Limit::Work`],
    /// [`crate::FlowOptions::work_limit`]). Its message starts with `not certified within
    /// the budget`.
    pub fn over_work() -> Self {
        Error::over_limit(Limit::Work, OVER_WORK)
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
    /// The same error, a refusal with the cause `cause` (contract E23); other errors
    /// unchanged.
    pub fn with_cause(self, cause: Cause) -> Self {
        match self {
            Error::Uncertified(r) => Error::Uncertified(Refusal { cause, ..r }),
            other => other,
        }
    }
    /// The same error, its message (a refusal's) with `more` appended; other errors unchanged.
    pub(crate) fn with_more(self, more: &str) -> Self {
        match self {
            Error::Uncertified(r) => Error::Uncertified(Refusal {
                message: format!("{}{more}", r.message),
                ..r
            }),
            other => other,
        }
    }
    /// The cause of a refusal (contract E23); `None` for input errors and internal faults.
    pub fn cause(&self) -> Option<Cause> {
        match self {
            Error::Uncertified(r) => Some(r.cause),
            _ => None,
        }
    }
    /// The kind of a refusal; `None` for input errors and internal faults.
    pub fn reason(&self) -> Option<Reason> {
        match self {
            Error::Uncertified(r) => Some(r.reason),
            _ => None,
        }
    }
    /// The budget a [`Reason::Budget`] refusal spent; `None` otherwise.
    pub fn limit(&self) -> Option<Limit> {
        match self {
            Error::Uncertified(r) => r.limit,
            _ => None,
        }
    }
    /// Which part of the request an input error is about; `None` for the other variants.
    pub fn input_kind(&self) -> Option<&InputKind> {
        match self {
            Error::Input(e) => Some(&e.kind),
            _ => None,
        }
    }
    /// Whether a budget was spent ([`Reason::Budget`]): the request may succeed with more.
    pub fn is_budget(&self) -> bool {
        self.reason() == Some(Reason::Budget)
    }
    /// The message alone, without the prefix that `Display` adds.
    pub fn message(&self) -> &str {
        match self {
            Error::Input(e) => &e.message,
            Error::Internal(e) => &e.message,
            Error::Uncertified(r) => &r.message,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Input(e) => write!(f, "invalid input: {}", e.message),
            Error::Uncertified(r) => write!(f, "could not certify: {}", r.message),
            Error::Internal(e) => write!(f, "internal error (a bug of dalembert): {}", e.message),
        }
    }
}

impl std::error::Error for Error {}

#[cfg(test)]
mod tests {
    use super::*;

    fn composes<E: std::error::Error + Send + Sync + 'static>() {}

    #[test]
    fn every_error_type_composes() {
        composes::<Error>();
        composes::<InputError>();
        composes::<InternalError>();
        composes::<Refusal>();
        composes::<crate::schemes::SchemeError>();
        composes::<crate::newton::NewtonFailure>();
    }

    #[test]
    fn kinds_are_kept_and_the_text_is_unchanged() {
        let e = Error::input_key("h", "`h` must be > 0");
        assert_eq!(e.input_kind(), Some(&InputKind::Key("h".into())));
        assert_eq!(e.to_string(), "invalid input: `h` must be > 0");
        let e = Error::over_work().reached(2.5);
        assert_eq!(
            (e.limit(), e.reason()),
            (Some(Limit::Work), Some(Reason::Budget))
        );
        assert!(matches!(&e, Error::Uncertified(r) if r.reached == Some(2.5)));
        let e = Error::internal_at(Invariant::Missing, "gone");
        assert_eq!(e.to_string(), "internal error (a bug of dalembert): gone");
        assert!(matches!(
            e,
            Error::Internal(InternalError {
                invariant: Invariant::Missing,
                ..
            })
        ));
        assert_eq!(Error::uncertified("x").limit(), None);
    }
}
