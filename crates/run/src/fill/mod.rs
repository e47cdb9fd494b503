//! Filling a container: each particle drawn (component, then radius), then placed by random
//! sequential insertion in batches that fall under gravity (docs/physics.md §10.8); the slab's
//! in its x–z outline, the 3D containers' in a band of their volume.

mod batch;
mod draw;
mod silo;
mod slab;

pub use draw::{Draw, ParticleDraws};
pub use silo::{insert_silo_batch, FillRegion};
pub use slab::{insert_slab_batch, inside_slab, Inserted};
