//! Measures of a third-body layer (TBL) under sliding, paper 004 section 3: plain functions of
//! profiles and time series, shared by any sliding simulation (DEM here, MD alike):
//! - [`profile`]: binned horizontal velocity and mass density over the current height H (400 bins in
//!   the paper, Fig. 4);
//! - [`bounds`]: the TBL's boundaries where the velocity crosses 0.1 v0 and 0.9 v0, h_TBL / H;
//! - [`filter`]: the moving average of h_TBL over time (Fig. 5) and the Savitzky-Golay filter of the
//!   density profile (order 3 on 7 samples);
//! - [`fit`]: the least-squares Gaussian whose minimum is rho_TBL (Fig. 4b);
//! - [`layer`]: one profile to its boundaries, filtered density and rho_TBL;
//! - [`regime`]: the steady state and the regime label of a run (mixed with wear particles, shear
//!   band, growing large particles; Fig. 3; or a TBL that has reached a rigid body, the phase the
//!   paper drops) from these measures and p_T;
//! - [`mod@wear_particles`]: the loose clusters of layer material between two frames (Fig. 3a and 3c),
//!   the junction's cluster rule applied to the layer.

pub mod bounds;
pub mod filter;
pub mod fit;
pub mod layer;
pub mod profile;
pub mod regime;
pub mod wear_particles;

pub use bounds::{tbl_bounds, TblBounds};
pub use filter::{moving_average, savitzky_golay};
pub use fit::{fit_gaussian_dip, GaussFit};
pub use layer::{layer_agitation, measure_layer, LayerMeasures, LayerParams};
pub use profile::{sphere_slab_volume, Bins, Profile, ProfileParticles, ProfileSums};
pub use regime::{
    classify_regime, erratic_spread, shear_traction, steady_mean, touches_body, Regime, RegimeData,
    RegimeParams,
};
pub use wear_particles::{wear_particles, LayerGeometry, WearParticles};
