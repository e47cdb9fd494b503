//! How a silo's curved walls are represented in the engine, shared by the cylinder and the
//! cuboid (and the mesh's orifice): exact shapes or triangle meshes of a number of segments.

use serde::{Deserialize, Serialize};

/// Default number of segments around the axis of a meshed cylinder or cone, and of the
/// orifice's polygon: 96 segments put the chord's midpoint 0.05 % of the radius inside the
/// circle, far below a particle radius for any silo a few diameters wide.
pub const DEFAULT_MESH_SEGMENTS: usize = 96;

/// Fewest and most segments around a circle (a triangle must stay a reasonable fraction of
/// the silo; more than a few thousand only costs memory).
pub const MESH_SEGMENTS_RANGE: (i64, i64) = (12, 4096);

/// How curved walls are represented in the engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WallSurface {
    /// Exact cylinder and cone (the engine's frustum shape, docs/physics.md §5.2).
    Smooth,
    /// Triangle meshes of `mesh_segments` strips around the axis (§5.3).
    Meshed,
}
