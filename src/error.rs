//! The typed failures of the library (spec/00-overview.md, "Failure").

use std::fmt;

/// The message of [`Error::over_budget`].
pub const OVER_BUDGET: &str = "not certified within the budget (the deadline passed)";

/// Why a request was not answered. `Input` maps to exit status 2, `Uncertified` to 3.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Error {
    /// The request is malformed: unknown scene or parameter, wrong dimension, non-finite
    /// number, negative time, ...
    Input(String),
    /// The request is well formed but no enclosure could be proved; nothing is returned.
    Uncertified(String),
    /// A fault of this crate, not of the request and not a failed proof (a bug to report);
    /// nothing is returned. Exit status 3, like every answer that certifies nothing.
    Internal(String),
}

impl Error {
    pub fn input(msg: impl Into<String>) -> Self {
        Error::Input(msg.into())
    }
    pub fn uncertified(msg: impl Into<String>) -> Self {
        Error::Uncertified(msg.into())
    }
    pub fn internal(msg: impl Into<String>) -> Self {
        Error::Internal(msg.into())
    }
    /// The refusal of work that ran past its time budget (exit 3). Its message starts with
    /// [`OVER_BUDGET`] so that a client can tell it from other refusals.
    pub fn over_budget() -> Self {
        Error::Uncertified(OVER_BUDGET.to_string())
    }
    /// `Err(over_budget())` once `deadline` has passed; `Ok` when there is none.
    pub fn check_deadline(deadline: Option<std::time::Instant>) -> Result<(), Error> {
        match deadline {
            Some(d) if std::time::Instant::now() >= d => Err(Error::over_budget()),
            _ => Ok(()),
        }
    }
    /// The command line's exit status for this error.
    pub fn code(&self) -> i32 {
        match self {
            Error::Input(_) => 2,
            Error::Uncertified(_) | Error::Internal(_) => 3,
        }
    }
    pub fn message(&self) -> &str {
        match self {
            Error::Input(m) | Error::Uncertified(m) | Error::Internal(m) => m,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Input(m) => write!(f, "invalid input: {m}"),
            Error::Uncertified(m) => write!(f, "could not certify: {m}"),
            Error::Internal(m) => write!(f, "internal error (a bug of dalembert): {m}"),
        }
    }
}

impl std::error::Error for Error {}
