//! hopperflow's DEM engine.
