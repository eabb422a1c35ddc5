//! `dalembert`: a verified reference implementation of exact discrete nonholonomic
//! mechanics (Anahory Simoes, Marrero, Martin de Diego) with interval arithmetic.
//!
//! The mathematics is in `spec/`; every function that returns an enclosure says under
//! `# Containment` what it proves, and cites the spec's equations.

// Forward-mode AD legitimately adds inside Mul and Div impls.
#![allow(clippy::suspicious_arithmetic_impl)]
// Index loops mirror the formulas of spec/ (sums over i, j): kept on purpose.
#![allow(clippy::needless_range_loop)]
// Every public item is documented (issue 16); clippy's `-D warnings` keeps it so.
#![warn(missing_docs)]

// The public surface: what a user of the library needs, and nothing else (spec/design.md,
// "Public surface"). The scene language, the exact objects, the oracle, the float schemes and
// the testing kit are public; the tapes, the dynamics' geometry and the generic validated ODE
// layer are internal.
#[cfg(feature = "cli")]
pub mod cli;
pub mod elementary;
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
#[cfg(feature = "cli")]
pub mod report;
pub mod scalar;
pub mod scene;
pub mod schemes;
pub mod testing;

/// Internal layers, public only with the `internals` feature (the crate's own tests reach
/// them; no stability is promised). Without it they are crate-private.
macro_rules! internal {
    ($($(#[$m:meta])* $name:ident;)*) => {$(
        $(#[$m])*
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub mod $name;
        $(#[$m])*
        #[cfg(not(feature = "internals"))]
        mod $name;
    )*};
}
internal! {
    /// The geometry of a scene at a configuration (spec chapters 3-4).
    dynamics;
    /// The generic validated ODE layer (spec chapter 5).
    enclosure;
    /// Recorded straight-line programs (spec eq. (3.16)).
    tape;
}

mod dot;
mod error;
mod readable;

pub use enclosure::{Basis, FlowOptions, FlowStats};
pub use error::{Error, InputError, InputKind, InternalError, Invariant, Limit, Reason, Refusal};
pub use flow::{flow, FlowEnclosure};
pub use model::Model;
pub use progress::Progress;
pub use scene::{AnyScene, Scene};
pub use tape::work_done;
