//! Case and sweep files: raw TOML structs, then validated domain types.
