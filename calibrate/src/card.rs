//! The calibrated parameter card: everything needed to rebuild the calibrated [`PairModel`] and the
//! sample it was calibrated on, what was measured, and where it came from. TOML; every `cgdem`
//! scenario rebuilds its model with [`CalibratedCard::pair_model`] (or reads the `[model]` table, a
//! plain serialised `PairModel`).

use std::path::Path;

use dem::material::PairModel;
use dem::sample::RelaxConfig;
use dem::sample::SampleSpec;
use serde::{Deserialize, Serialize};

use crate::config::SiMaterial;
use crate::error::{CalibrateError, Result};
use crate::executor::Status;
use crate::patch_problem::{Properties, TestSettings};

/// Where the card came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// "cgdem calibrate <version>".
    pub tool: String,
    /// Fingerprint of the calibration inputs (the checkpoint's).
    pub fingerprint: String,
    pub status: Status,
    pub iterations: usize,
    pub evaluations: usize,
    /// Wall time of the process that finished the calibration, s (a resumed run counts its own part).
    pub wall_seconds: f64,
    /// Free-text notes.
    pub notes: Vec<String>,
}

/// The card.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CalibratedCard {
    /// Engine unit system: "reduced" or "nano" (nm, ns, ag; stress in MPa).
    pub units: String,
    /// The calibrated model: material in engine units, law, switches, damping and multipliers.
    pub model: PairModel,
    /// The SI input, when the material was given in SI.
    #[serde(default)]
    pub material_si: Option<SiMaterial>,
    /// Sample recipe (generated with the *first-guess* multipliers, as in the calibration) and the
    /// saved sample file next to the card.
    pub sample: SampleSpec,
    pub sample_file: String,
    pub relax: RelaxConfig,
    /// Patch-test settings of the calibration.
    pub tests: TestSettings,
    /// Targets (strengths from eq 20 at the sample's d0), first-guess and calibrated measurements,
    /// engine units.
    pub targets: Properties,
    pub uncalibrated: Properties,
    pub calibrated: Properties,
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
