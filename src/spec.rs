//! The specification: the mathematics the code implements, with the numbered equations and
//! theorems that the rest of this documentation cites (`spec (5.8)` is equation (5.8) of
//! [chapter 5](enclosure)). Documentation only: this module holds no code.
//!
//! These pages are the files of the crate's `spec/` directory, rendered as they are.
//!
//! - [0. Overview: what `dalembert` proves](overview): the global promise and the failure model
//! - [1. Scalars](scalars)
//! - [2. Tapes and Taylor series](taylor)
//! - [3. Scenes](scenes)
//! - [4. The continuous nonholonomic dynamics](dynamics)
//! - [5. The validated integrator](enclosure) (Theorem 5.1: what a flow proves)
//! - [6. The exact discrete objects](exact_discrete)
//! - [7. The float schemes DLA and MLA](schemes)
//! - [8. The oracle: verdicts, batch protocol, fuzzing](oracle) (Theorem 8.1)
//! - [9. Figures and the stability table](report)
//! - [10. Scene files](scene_files)
//! - [11. Testing other integrators](testing)
//! - [12. Precision beyond binary64](precision): the interval types, their rounding proofs, the engine at any precision
//! - [The command-line contract](contract): commands, flags, output and exit statuses
//! - [Design and house style](design): the layers and why

#[doc = include_str!("../spec/00-overview.md")]
pub mod overview {}

#[doc = include_str!("../spec/01-scalars.md")]
pub mod scalars {}

#[doc = include_str!("../spec/02-taylor.md")]
pub mod taylor {}

#[doc = include_str!("../spec/03-scenes.md")]
pub mod scenes {}

#[doc = include_str!("../spec/04-dynamics.md")]
pub mod dynamics {}

#[doc = include_str!("../spec/05-enclosure.md")]
pub mod enclosure {}

#[doc = include_str!("../spec/06-exact-discrete.md")]
pub mod exact_discrete {}

#[doc = include_str!("../spec/07-schemes.md")]
pub mod schemes {}

#[doc = include_str!("../spec/08-oracle.md")]
pub mod oracle {}

#[doc = include_str!("../spec/09-report.md")]
pub mod report {}

#[doc = include_str!("../spec/10-scene-files.md")]
pub mod scene_files {}

#[doc = include_str!("../spec/11-testing.md")]
pub mod testing {}

#[doc = include_str!("../spec/12-precision.md")]
pub mod precision {}

#[doc = include_str!("../spec/contract.md")]
pub mod contract {}

#[doc = include_str!("../spec/design.md")]
pub mod design {}
