//! Geometry of 3D silos with a circular orifice on a vertical axis: the volume of a sphere in
//! a horizontal slab, whole and split into annuli about the axis, for radial packing-fraction
//! profiles φ(r).

mod disc_overlap;
mod gauss_legendre;
mod radial_fraction;
mod sphere_slab;

pub use disc_overlap::{disc_in_annulus_area, disc_in_disc_area};
pub use radial_fraction::radial_volume_fractions;
pub use sphere_slab::{sphere_slab_radial_volumes, sphere_slab_volume, spherical_cap_volume};
