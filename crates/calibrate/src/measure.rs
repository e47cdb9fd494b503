//! The measures of a finished run: numbers in its `summary.json`, named by dotted path.

use serde_json::Value;

/// The number at `measure` (e.g. `repose.angle_deg`) in a summary; `None` when the path is
/// absent, null or not a number.
pub fn measure_value(summary: &Value, measure: &str) -> Option<f64> {
    let mut node = summary;
    for part in measure.split('.') {
        node = node.get(part)?;
    }
    node.as_f64().filter(|v| v.is_finite())
}

/// Whether `measure` names a field of the summary at all, null included: a run may have no
/// value for a measure it does have (a clogged run's discharge rate), which is not a typo.
pub fn has_measure(summary: &Value, measure: &str) -> bool {
    let mut node = summary;
    for part in measure.split('.') {
        match node.get(part) {
            Some(next) => node = next,
            // A null section (an optional record this run did not make) holds the field too.
            None => return node.is_null(),
        }
    }
    true
}

/// Every dotted path of a number in a summary, in key order: what a target may name.
pub fn numeric_measures(summary: &Value) -> Vec<String> {
    fn walk(prefix: &str, node: &Value, out: &mut Vec<String>) {
        match node {
            Value::Number(_) => out.push(prefix.to_string()),
            Value::Object(map) => {
                for (key, value) in map {
                    let path = if prefix.is_empty() {
                        key.clone()
                    } else {
                        format!("{prefix}.{key}")
                    };
                    walk(&path, value, out);
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk("", summary, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dotted_paths_reach_nested_numbers_only() {
        let summary: Value = serde_json::json!({
            "discharge_rate": 0.05,
            "repose": {"angle_deg": 31.5, "sectors": 8},
            "arch": null,
            "stop_reason": "empty"
        });
        assert_eq!(measure_value(&summary, "discharge_rate"), Some(0.05));
        assert_eq!(measure_value(&summary, "repose.angle_deg"), Some(31.5));
        assert_eq!(measure_value(&summary, "arch.particles"), None);
        assert_eq!(measure_value(&summary, "stop_reason"), None);
        assert!(has_measure(&summary, "arch.particles"));
        assert!(!has_measure(&summary, "repose.angle"));
        assert!(!has_measure(&summary, "discharge"));
        assert_eq!(
            numeric_measures(&summary),
            vec!["discharge_rate", "repose.angle_deg", "repose.sectors"]
        );
    }
}
