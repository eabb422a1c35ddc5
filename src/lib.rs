//! `dalembert`: a verified reference implementation of exact discrete nonholonomic
//! mechanics (Anahory Simoes, Marrero, Martin de Diego) with interval arithmetic.
//!
//! The mathematics is in `spec/`; every function that returns an enclosure says under
//! `# Containment` what it proves, and cites the spec's equations.

// Forward-mode AD legitimately adds inside Mul and Div impls.
#![allow(clippy::suspicious_arithmetic_impl)]
// Index loops mirror the formulas of spec/ (sums over i, j): kept on purpose.
#![allow(clippy::needless_range_loop)]

#[cfg(feature = "cli")]
pub mod cli;
pub mod dynamics;
pub mod elementary;
pub mod enclosure;
pub mod exact;
pub mod flow;
#[cfg(feature = "fuzzing")]
pub mod fuzzing;
pub mod model;
pub mod newton;
pub mod oracle;
mod progress;
#[cfg(feature = "cli")]
pub mod protocol;
pub mod report;
pub mod scalar;
pub mod scene;
pub mod schemes;
pub mod tape;
pub mod testing;

mod error;
mod readable;

pub use enclosure::{FlowOptions, FlowStats};
pub use error::{Error, Reason, Refusal};
pub use flow::{flow, FlowEnclosure};
pub use model::Model;
pub use progress::Progress;
pub use scene::AnyScene;
