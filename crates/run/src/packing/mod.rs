//! Packing files: particles placed at rest by another code or run (CSV or VTU), read, checked
//! against the case's container and materials, and placed (docs/user-guide.md).

mod read;
mod vtu;

pub use read::{
    packing_count, read_packing, PackedParticle, Packing, PackingError, PackingPlace,
    PackingProblem, PACKING_COLUMNS, PACKING_OVERLAP_FRACTION, RADIUS_TOLERANCE,
    REQUIRED_PACKING_COLUMNS,
};
