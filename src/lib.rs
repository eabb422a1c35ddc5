//! `dalembert`: a verified reference implementation of exact discrete nonholonomic
//! mechanics (Anahory Simoes, Marrero, Martin de Diego, *Exact discrete Lagrangian mechanics
//! for nonholonomic mechanics*) with interval arithmetic ([inari](https://docs.rs/inari)).
//!
//! It encloses the exact nonholonomic flow ([`flow()`]), the exact retractions, the defect of
//! a pair with respect to the exact discrete constraint submanifold `M_h^{e,nh}`, the exact
//! discrete flow and Legendre transforms ([`exact`]), and ships the paper's float schemes DLA
//! and MLA ([`schemes`]). It is an oracle for people who write nonholonomic integrators:
//! [`oracle`] and [`testing`] turn a candidate trajectory into certified verdicts. Every
//! enclosure it returns contains the exact value; when a proof fails the answer is
//! [`Error::Uncertified`], never a number.
//!
//! ```
//! use dalembert::{flow, AnyScene, FlowOptions, Model};
//! let model = Model::new(&AnyScene::new("particle", &[])?)?;
//! let e = flow(&model, &[0.0, 0.0, 0.0], &[0.8, 0.8], 600.0, &FlowOptions::default())?;
//! assert!(e.q[0].wid() < 1e-9); // e.q, e.u, e.v: intervals containing the exact state
//! # Ok::<(), dalembert::Error>(())
//! ```
//!
//! # Depending on the crate
//!
//! ```toml
//! [dependencies]
//! dalembert = { version = "0.1", default-features = false }   # the mathematics alone
//! ```
//!
//! Features: `cli` (default: the command line, the JSON protocol `protocol`, scene files),
//! `scene-files` (scene files and inline JSON scenes without the command line), `proptest`
//! and `quickcheck` (generators of admissible inputs: `testing::strategies`,
//! `testing::quickcheck_inputs`), `fuzzing` (the fuzz targets' checks and `testing::fuzz`), `internals`
//! (the crate's own tests; no stability promised).
//!
//! # The CPU flag
//!
//! inari 2.0 needs AVX and FMA on x86_64: a crate that depends on `dalembert` (or on inari)
//! must be compiled with them, for example in its `.cargo/config.toml`:
//!
//! ```toml
//! [build]
//! rustflags = ["-Ctarget-feature=+avx,+fma"]   # the minimum
//! # rustflags = ["-Ctarget-cpu=haswell"]        # a portable x86_64 build
//! # rustflags = ["-Ctarget-cpu=native"]         # this machine (AVX-512 where it has it)
//! ```
//!
//! `-Ctarget-cpu=native` also lets inari and the kernels of [spec (1.4)](crate::spec::scalars) use AVX-512 where the
//! CPU has it: faster, the same answers bit for bit. AArch64 needs no flag.
//!
//! # The mathematics
//!
//! The [`spec`] module renders the specification: the numbered equations and theorems that
//! the documentation cites (`spec (5.8)`, `spec Theorem 8.1`). Every function that returns an
//! enclosure says under `# Containment` what it proves. Start with the
//! [overview](spec::overview) (the global promise and the failure model) and
//! [chapter 5](spec::enclosure) (the validated integrator, Theorem 5.1); the command line is
//! specified in [the contract](spec::contract).

#![cfg_attr(docsrs, feature(doc_cfg))]
// Forward-mode AD legitimately adds inside Mul and Div impls.
#![allow(clippy::suspicious_arithmetic_impl)]
// Index loops mirror the formulas of spec/ (sums over i, j): kept on purpose.
#![allow(clippy::needless_range_loop)]
// Every public item is documented; clippy's `-D warnings` keeps it so.
#![warn(missing_docs)]
// Every public type prints with `{:?}` (answers show their intervals as `[lo, hi]`).
#![warn(missing_debug_implementations)]

// The public surface: what a user of the library needs, and nothing else (spec/design.md,
// "Public surface"). The scene language, the exact objects, the oracle, the float schemes and
// the testing kit are public; the tapes, the dynamics' geometry and the generic validated ODE
// layer are internal.
#[cfg(feature = "cli")]
#[cfg_attr(docsrs, doc(cfg(feature = "cli")))]
pub mod cli;
pub mod elementary;
pub mod exact;
pub mod flow;
#[cfg(feature = "fuzzing")]
#[cfg_attr(docsrs, doc(cfg(feature = "fuzzing")))]
pub mod fuzzing;
mod interval;
pub mod model;
pub mod newton;
pub mod oracle;
pub mod precision;
mod progress;
#[cfg(feature = "cli")]
#[cfg_attr(docsrs, doc(cfg(feature = "cli")))]
pub mod protocol;
#[cfg(feature = "cli")]
#[cfg_attr(docsrs, doc(cfg(feature = "cli")))]
pub mod report;
pub mod scalar;
pub mod scene;
pub mod schemes;
pub mod spec;
pub mod testing;

// The answer structs (those a user receives, not builds: `FlowEnclosure`, `Retraction`,
// `Verdict`, ...) are `#[non_exhaustive]`, so that a field can be added without breaking a
// user, who still reads and compares them; not with the `internals` feature, under which the
// crate's own tests build answers by hand (`cfg_attr(not(feature = "internals"), ..)`).

/// Internal layers, public only with the `internals` feature (the crate's own tests reach
/// them; no stability is promised). Without it they are crate-private.
macro_rules! internal {
    ($($(#[$m:meta])* $name:ident;)*) => {$(
        $(#[$m])*
        #[cfg(feature = "internals")]
        #[cfg_attr(docsrs, doc(cfg(feature = "internals")))]
        #[doc(hidden)]
        pub mod $name;
        $(#[$m])*
        #[cfg(not(feature = "internals"))]
        mod $name;
    )*};
}
internal! {
    /// The geometry of a scene at a configuration ([spec chapters 3-4](crate::spec::scenes)).
    dynamics;
    /// The generic validated ODE layer ([spec chapter 5](crate::spec::enclosure)).
    enclosure;
    /// Recorded straight-line programs ([spec eq. (3.16)](crate::spec::scenes)).
    tape;
}

mod dot;
mod error;

pub use enclosure::Ival;
pub use enclosure::{Basis, FlowOptions, FlowStats};
pub use error::{
    Cause, Error, InputError, InputKind, InternalError, Invariant, Limit, Reason, Refusal,
};
pub use flow::{flow, flow_at_in, FlowEnclosure};
pub use interval::{DecimalInterval, Interval, OutwardDecimal};
pub use model::Model;
pub use progress::Progress;
pub use scene::{AnyScene, Scene};
pub use tape::work_done;

// The README's Rust blocks compile and run as doctests (`cargo test --doc`); they use the
// command line's scene files and the proptest generators.
#[cfg(all(doctest, feature = "cli", feature = "proptest"))]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
