//! Discharge-rate time series: binned rates, the steady window, block-averaged means and
//! the regression rate from cumulative mass.

mod blocking;
mod cumulative_rate;
mod mean_rate;
mod rate_series;
mod steady_window;

pub use blocking::{block_average, BlockingAnalysis, BlockingLevel};
pub use cumulative_rate::{rate_from_cumulative_mass, CumulativeRate};
pub use mean_rate::{mean_rate, MeanRate};
pub use rate_series::RateSeries;
pub use steady_window::{find_steady_window, SteadyWindow, SteadyWindowOptions};
