//! Rigid clumps: bodies made of overlapping or touching member spheres, fixed in one frame
//! (docs/physics.md §11). This module holds what makes a body of a clump: its members
//! validated ([`ClumpShape`]), the mass properties of their union (`mass`, over the closed
//! forms of `cap`), the principal frame (`principal`), the torque-free rotation step that
//! turns it (`rotation`), and the clumps of a simulation with their part of a step
//! (`bodies`).

mod bodies;
pub mod cap;
mod mass;
mod mesh_fill;
mod principal;
pub mod rotation;
mod shape;

pub use bodies::ClumpSet;
pub use mass::{union_moments, Ball, REMAINDER_LINES};
pub use mesh_fill::{fill_mesh, FilledMesh, MAX_FILL_SPHERES};
pub use principal::{principal_frame, rotation_quaternion};
pub use shape::{ClumpBody, ClumpError, ClumpShape, MAX_ROD_BEADS};
