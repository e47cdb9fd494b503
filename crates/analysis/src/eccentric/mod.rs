//! Eccentric outlets (paper Sec. 4.2, Eqs. 15–18, Table 3, Figs. 10–16): asymmetric profile
//! fits, the σ_s1(s*) law, the φ_max(R) fit, the corrected Eq. 18 and W/W₀ against s*.

mod asymmetric_profile;
mod eccentric_rate;
mod exponential_approach;
mod geometry;
mod relative_rate;

pub use asymmetric_profile::{
    asymmetric_profile, fit_asymmetric_profile, fit_eccentric_packing_profiles,
    fit_eccentric_velocity_profiles, AsymmetricProfileFit, AsymmetricProfileOptions,
};
pub use eccentric_rate::{eccentric_discharge_rate, EccentricFlowParameters};
pub use exponential_approach::{
    exponential_approach, fit_exponential_approach, ExponentialApproachFit,
};
pub use geometry::{normalised_eccentricity, outlet_offset};
pub use relative_rate::{relative_discharge_rates, RelativeRate};

use crate::error::AnalysisResult;
use crate::selfsimilar::{fit_packing_saturation, PackingSaturationFit};

/// φ_max(R) fit of paper Fig. 13: the same form as Eq. 12, φ_max = φ∞(1 − τ₁e^{−2τ₂R}) with
/// R in metres at the API and τ₂ in 1/mm (see [`fit_packing_saturation`]). The paper finds
/// τ₁ = 5.34, τ₂ = 0.19 for s ≥ 6 mm and τ₁ = 3.74, τ₂ = 0.18 for s = 0.
pub fn fit_maximum_packing(
    radii: &[f64],
    maxima: &[f64],
    sigma: Option<&[f64]>,
) -> AnalysisResult<PackingSaturationFit> {
    fit_packing_saturation(radii, maxima, sigma)
}
