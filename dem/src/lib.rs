//! CG-DEM engine.
