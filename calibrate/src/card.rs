//! The calibrated parameter card: everything needed to rebuild the calibrated [`PairModel`] and new
//! samples of its recipe, what was measured during the calibration and on fresh samples afterwards,
//! and where it came from. TOML. A scenario reads it with
//!
//! ```no_run
//! # fn main() -> calibrate::Result<()> {
//! let card = calibrate::CalibratedCard::read(std::path::Path::new("card.toml"))?;
//! let model = card.pair_model()?; // dem::PairModel: material (engine units), law, multipliers
//! if let Some(v) = &card.verification {
//!     // Measured on samples the calibration never saw: mean and spread per property, and d*.
//!     println!("E {} (spread {:.1} %), d* {}", v.young_modulus.mean, 100.0 * v.young_modulus.spread, v.dstar);
//! }
//! # Ok(()) }
//! ```
//!
//! The `[model]` table is a plain serialised `PairModel`, so tools that do not link this crate can
//! read it too. A card belongs to its *recipe* (`sample`, `relax`): relax a new sample of that recipe
//! (any seed, any size) with the card's model and the verified figures hold for it.

use std::path::Path;

use dem::material::{PairModel, SiMaterial};
use dem::sample::RelaxConfig;
use dem::sample::SampleSpec;
use serde::{Deserialize, Serialize};

use crate::error::{CalibrateError, Result};
use crate::executor::Status;
use crate::patch_problem::{Properties, TestSettings};
use crate::verification::Verification;

/// Where the card came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// `"cgdem calibrate <version>"`.
    pub tool: String,
    /// Fingerprint of the calibration inputs (the checkpoint's).
    pub fingerprint: String,
    pub status: Status,
    pub iterations: usize,
    pub evaluations: usize,
    /// Wall time of the calibration, s, summed over every process that ran it (as checkpointed), plus
    /// the verification of the process that wrote the card; and that verification's part.
    pub wall_seconds: f64,
    #[serde(default)]
    pub verification_seconds: f64,
    /// Free-text notes.
    pub notes: Vec<String>,
}

/// The card.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CalibratedCard {
    /// Engine unit system: "reduced" or "nano" (nm, ns, ag; stress in MPa, surface energy in mJ/m^2).
    pub units: String,
    /// Seeds of the samples every evaluation of the calibration relaxed (empty for a lattice or a
    /// file).
    pub seeds: Vec<u64>,
    /// The calibrated model: material in engine units, law, switches, damping and multipliers.
    pub model: PairModel,
    /// The SI input, when the material was given in SI.
    #[serde(default)]
    pub material_si: Option<SiMaterial>,
    /// The sample recipe the card is calibrated for (seed: the first calibration sample's).
    pub sample: SampleSpec,
    pub relax: RelaxConfig,
    /// Patch-test settings of the calibration.
    pub tests: TestSettings,
    /// Targets (strengths from eq 20 at the recipe's d0), and the means over the calibration samples
    /// at the first guess and at the calibrated model, engine units.
    pub targets: Properties,
    pub uncalibrated: Properties,
    pub calibrated: Properties,
    /// The calibrated model measured on fresh samples of the recipe (None if skipped).
    #[serde(default)]
    pub verification: Option<Verification>,
    pub provenance: Provenance,
}

impl CalibratedCard {
    /// The calibrated pair model, checked.
    pub fn pair_model(&self) -> Result<PairModel> {
        self.model.validate()?;
        Ok(self.model.clone())
    }

    pub fn to_toml(&self) -> Result<String> {
        toml::to_string_pretty(self).map_err(|e| CalibrateError::Format {
            path: "card".into(),
            reason: e.to_string(),
        })
    }

    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| CalibrateError::io(path, e))?;
        toml::from_str(&text).map_err(|e| CalibrateError::format(path, e))
    }

    pub fn write(&self, path: &Path) -> Result<()> {
        dem::io::checkpoint::write_atomic(path, self.to_toml()?.as_bytes())?;
        Ok(())
    }
}
