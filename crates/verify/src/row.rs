//! One line of the verification table: a quantity, its expected and measured values, and the verdict.

use serde::{Deserialize, Serialize};

/// One checked quantity. Serialised with exactly these six keys (the `hopperflow verify` table).
///
/// `tolerance` is absolute, in the unit of the quantity: the row passes when
/// |measured − expected| ≤ tolerance. Relative tolerances of the spec are converted to absolute
/// ones when the row is made, so that a reader of the table never has to guess which kind it is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The case, e.g. "CO1".
    pub test: String,
    /// What was measured, with its unit and the set-up that distinguishes it from its neighbours.
    pub quantity: String,
    /// Expected value (analytic, published or model-reference; see the case's documentation).
    pub expected: f64,
    /// Value measured with the engine.
    pub measured: f64,
    /// Largest accepted |measured − expected|, in the unit of the quantity.
    pub tolerance: f64,
    /// Whether |measured − expected| ≤ tolerance (false when the measurement is not finite).
    pub pass: bool,
}

impl Row {
    /// A row with an absolute tolerance.
    pub fn absolute(
        test: &str,
        quantity: impl Into<String>,
        expected: f64,
        measured: f64,
        tolerance: f64,
    ) -> Self {
        let pass = (measured - expected).abs() <= tolerance;
        Self {
            test: test.to_owned(),
            quantity: quantity.into(),
            expected,
            measured,
            tolerance,
            pass,
        }
    }

    /// A row with a tolerance relative to the expected value (`relative` = 0.01 for 1 %).
    pub fn relative(
        test: &str,
        quantity: impl Into<String>,
        expected: f64,
        measured: f64,
        relative: f64,
    ) -> Self {
        Self::absolute(
            test,
            quantity,
            expected,
            measured,
            relative * expected.abs(),
        )
    }

    /// A row that only checks that a non-negative quantity stays below `bound`
    /// (expected 0, tolerance `bound`): used for quantities the spec asks to record, not to match.
    pub fn bounded(test: &str, quantity: impl Into<String>, measured: f64, bound: f64) -> Self {
        Self::absolute(test, quantity, 0.0, measured, bound)
    }

    /// A failing row standing for a case that could not run.
    pub fn failed(test: &str, reason: &str) -> Self {
        Self {
            test: test.to_owned(),
            quantity: format!("case did not run: {reason}"),
            expected: f64::NAN,
            measured: f64::NAN,
            tolerance: 0.0,
            pass: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_pass_exactly_inside_their_tolerance_and_never_on_nan() {
        // The verdict is a plain comparison; these values are exactly representable.
        assert!(Row::absolute("T", "q", 1.0, 1.5, 0.5).pass);
        assert!(!Row::absolute("T", "q", 1.0, 1.5625, 0.5).pass);
        assert!(Row::relative("T", "q", -2.0, -2.015625, 0.0078125).pass);
        assert!(!Row::absolute("T", "q", 1.0, f64::NAN, 1e9).pass);
        assert!(!Row::failed("T", "x").pass);
    }

    #[test]
    fn json_has_exactly_the_six_documented_keys() {
        let v = serde_json::to_value(Row::absolute("CO1", "q", 1.0, 1.0, 0.0)).unwrap_or_default();
        let keys: Vec<&str> = v
            .as_object()
            .map(|o| o.keys().map(String::as_str).collect())
            .unwrap_or_default();
        assert_eq!(keys.len(), 6);
        for k in [
            "test",
            "quantity",
            "expected",
            "measured",
            "tolerance",
            "pass",
        ] {
            assert!(keys.contains(&k), "missing key {k}");
        }
    }
}
