//! Least-squares fitting: a nonlinear Levenberg–Marquardt wrapper and weighted linear regression.

mod linear;
mod nonlinear;
mod student;

pub use linear::{fit_line, fit_line_weighted, fit_proportional, LinearFit, ProportionalFit};
pub use nonlinear::{fit_curve, CurveData, NonlinearFit, ParameterBounds};
pub use student::student_t_quantile;
