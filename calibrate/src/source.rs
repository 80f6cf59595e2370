//! Where a scenario's material comes from: the `[material]` table of a scenario config (junction, d*
//! search) names exactly one source, and [`MaterialSource::resolve`] turns it into the pair model the
//! engine runs, in the unit system the config declares:
//! - `preset = "table5"`: paper 000 Table 5 silica (SI), closed-form parameters (eqs 7-13);
//! - `si = { ... }`: any material in SI (Pa, J/m^2, kg/m^3), closed form, converted with
//!   [`UnitSystem::NANO`];
//! - `engine = { ... }`: a material already in engine units (dimensionless studies), closed form;
//! - `md_card = "card.toml"`: the `[material]` table of an MD material card (`cgdem md silica`),
//!   closed form, with the exponent `scaling` (default 1/2);
//! - `card = "card.toml"`: a calibrated card (`cgdem calibrate`, `cgdem pipeline`): its calibrated
//!   model, in the card's own unit system, which must be the config's.
//!
//! Every output of a scenario states which source it used ([`ResolvedMaterial::description`]).

use std::path::{Path, PathBuf};

use dem::material::{ForceLaw, Material, PairModel, SiMaterial, DEFAULT_SCALING};
use dem::scenario::monolayer::MonolayerMaterial;
use dem::UnitSystem;
use serde::{Deserialize, Serialize};

use crate::card::CalibratedCard;
use crate::config::card_material;
use crate::error::{CalibrateError, Result};

/// The unit system a scenario config works in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Units {
    /// nm, ns, attogram: stress in MPa, velocity in m/s, energy in zJ (SI materials).
    Nano,
    /// Every scale one (dimensionless materials, the MD model material in LJ units).
    Reduced,
}

impl Units {
    /// The engine's unit system.
    pub fn system(self) -> UnitSystem {
        match self {
            Units::Nano => UnitSystem::NANO,
            Units::Reduced => UnitSystem::REDUCED,
        }
    }
    /// The name a calibrated card writes in its `units` field.
    pub fn card_name(self) -> &'static str {
        match self {
            Units::Nano => "nano",
            Units::Reduced => "reduced",
        }
    }
    /// Length unit, for outputs.
    pub fn length_name(self) -> &'static str {
        match self {
            Units::Nano => "nm",
            Units::Reduced => "length unit",
        }
    }
}

/// The named presets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// Paper 000 Table 5, amorphous silica.
    Table5,
}

/// One of the material sources of the module docs.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSource {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<Preset>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub si: Option<SiMaterial>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub engine: Option<Material>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub md_card: Option<PathBuf>,
    /// Exponent s of eq (10) for `md_card` (an MD card has none); default 1/2 (paper 000 section 4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scaling: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub card: Option<PathBuf>,
    /// A quasi-2D hex monolayer matched to 2D properties (the MD model material's card), in the
    /// config's units (`dem::scenario::monolayer`): closed-form pair parameters at nu = 1/4, with the
    /// measured `tensile_correction`; the target is the 2D card itself.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monolayer: Option<MonolayerMaterial>,
}

/// A source turned into what the engine runs.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedMaterial {
    pub model: PairModel,
    /// The target properties in engine units (for a calibrated card, its targets, not the design
    /// values the model may carry).
    pub target: Material,
    pub units: Units,
    /// One line saying where the model came from.
    pub description: String,
    /// The calibrated card, when the source was one.
    pub card: Option<CalibratedCard>,
}

impl ResolvedMaterial {
    /// A scenario's relaxation settings `own`, made as the card's samples were where the card
    /// requires it (relaxation by continuation, [`dem::sample::RelaxConfig::continuation`]): a card
    /// calibrated that way holds only on samples relaxed that way.
    pub fn relax_for(&self, own: dem::sample::RelaxConfig) -> dem::sample::RelaxConfig {
        let continued = self.card.as_ref().is_some_and(|c| c.relax.continuation);
        dem::sample::RelaxConfig {
            continuation: own.continuation || continued,
            ..own
        }
    }
}

impl MaterialSource {
    /// Resolves the source for a config in `units` whose relative paths start at `base`, with `law`
    /// for the closed-form sources.
    pub fn resolve(&self, base: &Path, units: Units, law: ForceLaw) -> Result<ResolvedMaterial> {
        let given = [
            self.preset.is_some(),
            self.si.is_some(),
            self.engine.is_some(),
            self.md_card.is_some(),
            self.card.is_some(),
            self.monolayer.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(CalibrateError::InvalidConfig(
                "[material] needs exactly one of preset, si, engine, md_card, card and monolayer"
                    .into(),
            ));
        }
        if self.scaling.is_some() && self.md_card.is_none() {
            return Err(CalibrateError::InvalidConfig(
                "[material] scaling goes with md_card only (the other sources carry their own)"
                    .into(),
            ));
        }
        let closed = |m: Material, description: String| -> Result<ResolvedMaterial> {
            let model = match law {
                ForceLaw::Cohesive => PairModel::cohesive(m.clone()),
                ForceLaw::NormalOnly => PairModel::normal_only(m.clone()),
            };
            model.validate()?;
            Ok(ResolvedMaterial {
                model,
                target: m,
                units,
                description,
                card: None,
            })
        };
        let si_units = |what: &str| -> Result<()> {
            if units == Units::Nano {
                Ok(())
            } else {
                Err(CalibrateError::InvalidConfig(format!(
                    "{what} is in SI, which the engine takes in nano units (nm, ns, ag): set units = \
                     \"nano\""
                )))
            }
        };
        if let Some(Preset::Table5) = self.preset {
            si_units("preset table5")?;
            return closed(
                Material::from_si(&SiMaterial::table5(), units.system()),
                "paper 000 Table 5 silica, closed-form parameters (eqs 7-13)".into(),
            );
        }
        if let Some(si) = &self.si {
            si_units("[material.si]")?;
            let name = si.name_or("SI material");
            return closed(
                Material::from_si(si, units.system()),
                format!("{name}, closed-form parameters (eqs 7-13)"),
            );
        }
        if let Some(m) = &self.monolayer {
            let (pair, target) = m.resolve()?;
            let model = PairModel::cohesive(pair);
            model.validate()?;
            return Ok(ResolvedMaterial {
                model,
                target,
                units,
                description: format!(
                    "hex monolayer of d0 = {} matched to 2D properties (E {}, sigma_N {} x {}, gamma {}), \
                     closed form of dem::scenario::monolayer",
                    m.d0,
                    m.properties.young_modulus,
                    m.properties.tensile_strength,
                    m.tensile_correction,
                    m.properties.surface_energy
                ),
                card: None,
            });
        }
        if let Some(m) = &self.engine {
            return closed(
                m.clone(),
                "material in engine units, closed-form parameters (eqs 7-13)".into(),
            );
        }
        if let Some(p) = &self.md_card {
            si_units("an MD material card")?;
            let path = base.join(p);
            let mut si = card_material(&path)?;
            si.scaling = Some(self.scaling.unwrap_or(DEFAULT_SCALING));
            return closed(
                Material::from_si(&si, units.system()),
                format!(
                    "MD material card {}, closed-form parameters (eqs 7-13)",
                    path.display()
                ),
            );
        }
        let path = base.join(self.card.as_ref().expect("one source is given"));
        let card = CalibratedCard::read(&path)?;
        if card.units != units.card_name() {
            return Err(CalibrateError::InvalidConfig(format!(
                "card {} is in {} units but the config says units = \"{}\": a card's numbers are in its \
                 own units, so the two must agree",
                path.display(),
                card.units,
                units.card_name()
            )));
        }
        if let Some(c) = card
            .verification
            .as_ref()
            .and_then(|v| v.compaction.as_ref())
            .filter(|c| !c.holds())
        {
            return Err(CalibrateError::CardCollapses {
                path: path.display().to_string(),
                detail: c.describe(),
            });
        }
        // The model may carry a design Poisson's ratio (config::design_poisson_ratio); the target's
        // is in the card's targets.
        let mut target = card.model.material.clone();
        if let Some(nu) = card.targets.poisson_ratio {
            target.poisson_ratio = nu;
        }
        Ok(ResolvedMaterial {
            model: card.pair_model()?,
            target,
            units,
            description: format!(
                "calibrated card {} ({:?} after {} iterations){}",
                path.display(),
                card.provenance.status,
                card.provenance.iterations,
                card.verification
                    .as_ref()
                    .map_or(String::from("; not verified on fresh samples"), |v| {
                        format!("; {}", verified_figures(v, units))
                    })
            ),
            card: Some(card),
        })
    }
}

/// The card's verification in one line, for a scenario to print beside its results: each property's
/// mean and spread on the fresh samples, the surface energy and d* of eq 22 from the measured values.
pub fn verified_figures(v: &crate::verification::Verification, units: Units) -> String {
    use crate::patch_problem::Target;
    let mut s = format!("verified on seeds {:?}:", v.seeds);
    for t in Target::ALL {
        let c = v.get(t);
        s.push_str(&format!(
            " {} {} ({:+.1} %, spread {:.1} %),",
            t.name(),
            dem::io::Sig(c.mean, 4),
            100.0 * c.mean_error(),
            100.0 * c.spread
        ));
    }
    s.push_str(&format!(
        " d* (eq 22) {} {} (targets: {}); {}",
        dem::io::Sig(v.dstar, 4),
        units.length_name(),
        dem::io::Sig(v.dstar_target, 4),
        v.compaction.as_ref().map_or_else(
            || "not verified under shear (a card from before the compaction test)".to_string(),
            |c| c.describe()
        )
    ));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn source(text: &str) -> Result<MaterialSource> {
        toml::from_str(text).map_err(|e| CalibrateError::InvalidConfig(e.to_string()))
    }

    #[test]
    fn table5_preset_is_the_closed_form_in_nano_units() {
        let m = source("preset = \"table5\"")
            .unwrap()
            .resolve(Path::new("."), Units::Nano, ForceLaw::Cohesive)
            .unwrap();
        assert!((m.model.material.young_modulus - 73_000.0).abs() < 1e-9); // MPa
        assert_eq!(m.model.material.scaling, 0.5);
        assert!(m.description.contains("Table 5"));
        assert!(m.card.is_none());
    }

    #[test]
    fn ambiguous_or_mismatched_sources_are_refused() {
        let two = source("preset = \"table5\"\ncard = \"x.toml\"").unwrap();
        assert!(two
            .resolve(Path::new("."), Units::Nano, ForceLaw::Cohesive)
            .is_err());
        assert!(MaterialSource::default()
            .resolve(Path::new("."), Units::Nano, ForceLaw::Cohesive)
            .is_err());
        let si_in_reduced = source("preset = \"table5\"").unwrap();
        let e = si_in_reduced
            .resolve(Path::new("."), Units::Reduced, ForceLaw::Cohesive)
            .unwrap_err();
        assert!(e.to_string().contains("units = \"nano\""), "{e}");
        assert!(source("presett = \"table5\"").is_err());
        let missing = source("card = \"/nonexistent/card.toml\"").unwrap();
        assert!(missing
            .resolve(Path::new("."), Units::Nano, ForceLaw::Cohesive)
            .is_err());
    }
}
