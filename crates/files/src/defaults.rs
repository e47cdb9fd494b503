//! What a saved case file means where it leaves a key out: a reader of saved runs (the report)
//! needs these without the case crate, which resolves whole cases for the engine.

/// g [m/s²] of a case that does not give `gravity`: the engine's and the paper's 9.81.
/// A case file holds the key only when it differs, so that the cases written before the key
/// existed keep their bytes and their configuration hashes.
pub const DEFAULT_GRAVITY: f64 = 9.81;
