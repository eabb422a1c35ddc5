//! `dalembert`: a verified reference implementation of exact discrete nonholonomic
//! mechanics (Anahory Simoes, Marrero, Martin de Diego) with interval arithmetic.
//!
//! The mathematics is in `spec/`; every function that returns an enclosure says under
//! `# Containment` what it proves, and cites the spec's equations.

pub mod dynamics;
pub mod enclosure;
pub mod model;
pub mod scalar;
pub mod scene;
pub mod tape;

mod error;

pub use enclosure::{flow, FlowEnclosure, FlowOptions, FlowStats};
pub use error::Error;
pub use model::Model;
pub use scene::AnyScene;
