//! Flow-rate laws: the self-similar prediction (paper Eq. 14) and its axisymmetric form for
//! circular orifices, and the hopper-angle corrections of Brown (paper Eq. 3) and Rose &
//! Tanaka used in the paper's Fig. 8c.

mod axisymmetric_rate;
mod beta;
mod brown;
mod quadrature;
mod rose_tanaka;
mod self_similar_rate;

pub use axisymmetric_rate::{axisymmetric_discharge_rate, AxisymmetricFlowParameters};
pub use beta::beta_function;
pub use brown::brown_ratio;
pub use quadrature::integrate;
pub use rose_tanaka::rose_tanaka_ratio;
pub use self_similar_rate::{self_similar_discharge_rate, SelfSimilarFlowParameters};
