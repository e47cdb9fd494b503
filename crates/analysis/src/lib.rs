//! Pure numerics for granular discharge analysis (Fan et al. 2023, Powder Technology 429, 118964):
//! steady-window detection, outlet profiles, least-squares fits, self-similar profile laws,
//! flow-rate predictions, the 2D Beverloo law and the eccentric-outlet extension; and for 3D
//! silos with a circular orifice, sphere volumes in slabs and annuli (radial φ(r)), the
//! axisymmetric self-similar rate, the 3D Beverloo law and Janssen's law.
//!
//! Everything is SI at the API (m, kg, s, rad). The crate does not depend on the DEM engine,
//! so saved series and tables can be re-analysed.

// Units are written in brackets, e.g. `[m]`, as the project style asks; rustdoc would
// otherwise read them as links.
#![allow(rustdoc::broken_intra_doc_links)]

pub mod beverloo;
pub mod beverloo3d;
pub mod calibration;
pub mod clogging;
pub mod eccentric;
mod error;
mod estimate;
pub mod fit;
pub mod flowrate;
pub mod geometry3d;
pub mod janssen;
pub mod orientation;
pub mod profile;
pub mod residence;
pub mod selfsimilar;
pub mod series;

#[cfg(test)]
mod test_support;

pub use error::{AnalysisError, AnalysisResult};
pub use estimate::{propagate, Estimate, Interval};
