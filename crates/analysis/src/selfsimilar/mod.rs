//! Self-similar outlet profiles of the centred hopper (paper Eqs. 10–12, Table 2, Figs. 3–7):
//! v/v_c = (1 − x*²)^a, φ/φ_c = (1 − x*²)^b, v_c = √(2γgR), φ_c = φ∞(1 − τ₁e^{−2τ₂R}).

mod centre_velocity;
mod packing_saturation;
mod power_profile;

pub use centre_velocity::{fit_centre_velocity, CentreVelocityFit};
pub use packing_saturation::{fit_packing_saturation, packing_saturation, PackingSaturationFit};
pub use power_profile::{
    fit_collapsed_power_profile, fit_power_profile, power_profile, PowerProfileFit,
    PROFILE_FIT_HALF_WIDTH,
};
