//! The calibration input (`cgdem calibrate <calibration.toml>`): target material (engine units, or SI
//! converted once at input with [`UnitSystem::NANO`]), force law, sample recipe, targets, unknowns,
//! first guess, solver settings and patch-test settings. Unreachable targets are refused here, before
//! any simulation.

use dem::material::{ForceLaw, Material, PairModel, ParamScale, SiMaterial, DEFAULT_SCALING};
use dem::sample::RelaxConfig;
use dem::sample::SampleSpec;
use dem::UnitSystem;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{CalibrateError, Result};
use crate::executor::Settings;
use crate::patch_problem::{Target, TestSettings, Unknown};
use crate::recipe::{recipe_samples, RecipeSettings, VerifySettings};

/// The `[material]` table of the material card at `path` (what `cgdem md silica` writes): the shared
/// [`SiMaterial`], whose scaling exponent is the file's or, where it names none (an MD card), 1/2.
pub fn card_material(path: &Path) -> Result<SiMaterial> {
    let text = std::fs::read_to_string(path).map_err(|e| CalibrateError::io(path, e))?;
    toml::from_str::<CardFile>(&text)
        .map(|card| card.material)
        .map_err(|e| CalibrateError::format(path, e))
}

/// Samples every evaluation of an SI card's calibration relaxes ([`CalibrationConfig::si_card`]),
/// with [`SI_THICKNESS`]. Measured on the MD silica card (docs/calibration.md, "The MD card on five
/// 12 d0 samples"): three 6 d0 samples stall with the shear strength 10 % low on fresh samples, five
/// 6 d0 samples converge and keep it 11 % low (thick samples are weaker in shear and scatter half as
/// much), five 12 d0 samples converge and verify within 3 % on all four properties.
pub const SI_SEEDS: u64 = 5;
/// See [`SI_SEEDS`]: the thickness (in d0) a junction's solids have, at twice a 6 d0 sample's cost.
pub const SI_THICKNESS: f64 = 12.0;
/// The recipe and solver of an SI card's calibration (the acceptance config of issue 16).
const SILICA: &str = include_str!("../../configs/calibrate-silica.toml");

fn half() -> f64 {
    DEFAULT_SCALING
}

/// An MD material card used as the calibration target.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CardRef {
    /// The card's path; a relative path is taken from the calibration config's folder.
    pub path: PathBuf,
    /// Exponent s of eq (10): a modelling choice the MD card cannot measure; default 0.5 (paper 000
    /// section 4, constant gamma for silica).
    #[serde(default = "half")]
    pub scaling: f64,
}

/// The part of a material card the calibration reads: its `[material]` table is an [`SiMaterial`]
/// (an MD card's has no scaling exponent; its other tables, such as the provenance, stay with the card).
#[derive(Debug, Deserialize)]
struct CardFile {
    material: SiMaterial,
}

/// The whole calibration input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationConfig {
    /// Target material in engine units; give this or `material_si`.
    #[serde(default)]
    pub material: Option<Material>,
    /// Target material in SI, converted with UnitSystem::NANO (nm, ns, ag).
    #[serde(default)]
    pub material_si: Option<SiMaterial>,
    /// Target material from an MD material card file (what `cgdem md silica` writes); read by
    /// [`CalibrationConfig::from_file`] into `material_si`. Default none.
    #[serde(default)]
    pub material_card: Option<CardRef>,
    /// Force law; default cohesive (paper 000).
    #[serde(default = "cohesive")]
    pub law: ForceLaw,
    /// Sample recipe (HCP, amorphous, or a saved file); an amorphous recipe's seed is the first of
    /// the calibration's seeds unless `[recipe] seeds` lists them.
    pub sample: SampleSpec,
    /// Which samples of the recipe every evaluation relaxes; default see [`RecipeSettings`].
    #[serde(default)]
    pub recipe: RecipeSettings,
    /// The fresh samples the card is verified on; default see [`VerifySettings`].
    #[serde(default)]
    pub verification: VerifySettings,
    /// Nominal diameter in metres (SI materials): replaces the recipe's d0_over_dc; default none.
    #[serde(default)]
    pub d0_m: Option<f64>,
    /// Relaxation of amorphous samples; default the paper's (section 3.2).
    #[serde(default)]
    pub relax: RelaxConfig,
    /// Residuals; default E, nu, sigma_N, sigma_T (the surface energy on request).
    #[serde(default = "default_targets")]
    pub targets: Vec<Target>,
    /// Unknowns; default all five for the cohesive law, k_N, delta_e, delta_f for normal-only.
    #[serde(default)]
    pub unknowns: Option<Vec<Unknown>>,
    /// First guess; default all multipliers 1 (the closed form, eqs 7-13).
    #[serde(default)]
    pub start: ParamScale,
    /// Solver settings; default see [`Settings`].
    #[serde(default)]
    pub solver: Settings,
    /// Patch-test settings; default see [`TestSettings`].
    #[serde(default)]
    pub tests: TestSettings,
}

fn cohesive() -> ForceLaw {
    ForceLaw::Cohesive
}

fn default_targets() -> Vec<Target> {
    vec![
        Target::YoungModulus,
        Target::PoissonRatio,
        Target::TensileStrength,
        Target::ShearStrength,
    ]
}

/// A checked configuration: the base model, the unit system and the resolved choices.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// Base model; its material is the target except for a design Poisson's ratio (see
    /// [`design_poisson_ratio`]).
    pub model: PairModel,
    /// The target material (strengths, nu ... the residuals are measured against).
    pub target: Material,
    /// Poisson's ratio the area coefficients A_N, A_T are computed from, when not the target's.
    pub design_poisson_ratio: Option<f64>,
    pub units: UnitSystem,
    /// The recipe (d0 resolved) and its distinct samples of every evaluation.
    pub sample: SampleSpec,
    pub samples: Vec<SampleSpec>,
    /// The calibration's seeds (empty for a lattice or a file).
    pub seeds: Vec<u64>,
    /// Nominal diameter of a generated recipe (engine units); a file's is read with the file.
    pub d0: Option<f64>,
    pub targets: Vec<Target>,
    pub unknowns: Vec<Unknown>,
    pub tests: TestSettings,
}

impl CalibrationConfig {
    /// `material` (engine units) on `sample`, every other field at the default a TOML file gets.
    pub fn new(material: Material, sample: SampleSpec) -> Self {
        CalibrationConfig {
            material: Some(material),
            material_si: None,
            material_card: None,
            law: cohesive(),
            sample,
            recipe: RecipeSettings::default(),
            verification: VerifySettings::default(),
            d0_m: None,
            relax: RelaxConfig::default(),
            targets: default_targets(),
            unknowns: None,
            start: ParamScale::default(),
            solver: Settings::default(),
            tests: TestSettings::default(),
        }
    }

    /// The main job's default calibration (`cgdem pipeline` without a card, and the report's
    /// calibration section): paper 000 Table 4 with Poisson's ratio `nu` on an HCP sample of
    /// `l_over_d0` x `l_over_d0` x 3 d0 at d0 = 0.6 d_c, at most 12 iterations (lattices converge in
    /// 2-8, docs/calibration.md).
    pub fn table4_hcp(nu: f64, l_over_d0: f64) -> Self {
        let sample = SampleSpec::Hcp {
            d0_over_dc: 0.6,
            l_over_d0,
            w_over_d0: 3.0,
        };
        let mut cfg = Self::new(Material::table4(nu), sample);
        cfg.solver.max_iterations = 12;
        cfg
    }

    /// The calibration of an SI material card (`cgdem pipeline --material CARD`, the report's MD
    /// chain): the recipe and solver of `configs/calibrate-silica.toml` (the junction's
    /// discretisation: amorphous, d0 = 3 nm, d_s = 0.75 d0, d_l = 7.5 nm, s = 1/2) with the card's
    /// material, on [`SI_SEEDS`] samples [`SI_THICKNESS`] d0 thick. The card's own exponent s, or the
    /// recipe's 1/2 when it names none (an MD card).
    pub fn si_card(mut material: SiMaterial) -> Result<Self> {
        let mut cfg = Self::from_toml(SILICA)?;
        material.scaling = material
            .scaling
            .or_else(|| cfg.material_si.as_ref().and_then(|t| t.scaling));
        cfg.material_si = Some(material);
        cfg.recipe.seeds = Some((1..=SI_SEEDS).collect());
        cfg.set_sample_size(None, Some(SI_THICKNESS));
        Ok(cfg)
    }

    /// Sets the sample's edge L and thickness W (in d0) where given (a sample read from a file has
    /// neither, and is left as it is).
    pub fn set_sample_size(&mut self, l_over_d0: Option<f64>, w_over_d0: Option<f64>) {
        if let SampleSpec::Hcp {
            l_over_d0: l,
            w_over_d0: w,
            ..
        }
        | SampleSpec::Amorphous {
            l_over_d0: l,
            w_over_d0: w,
            ..
        }
        | SampleSpec::HexMonolayer {
            l_over_d0: l,
            w_over_d0: w,
            ..
        } = &mut self.sample
        {
            *l = l_over_d0.unwrap_or(*l);
            *w = w_over_d0.unwrap_or(*w);
        }
    }

    pub fn from_toml(text: &str) -> Result<Self> {
        toml::from_str(text).map_err(|e| CalibrateError::InvalidConfig(e.to_string()))
    }

    /// Reads a config file, and the material card it names (if any) into `material_si`.
    pub fn from_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| CalibrateError::io(path, e))?;
        let mut cfg = Self::from_toml(&text)?;
        if let Some(card) = &cfg.material_card {
            if cfg.material.is_some() || cfg.material_si.is_some() {
                return Err(CalibrateError::InvalidConfig(
                    "give exactly one of [material], [material_si] and [material_card]".into(),
                ));
            }
            let card_path = path.parent().unwrap_or(Path::new(".")).join(&card.path);
            let mut m = card_material(&card_path)?;
            m.scaling = Some(card.scaling);
            cfg.material_si = Some(m);
        }
        Ok(cfg)
    }

    /// Checks everything that can be checked without a simulation, and refuses unreachable targets.
    pub fn prepare(&self) -> Result<Prepared> {
        let (target, units) = match (&self.material, &self.material_si) {
            (Some(m), None) => (m.clone(), UnitSystem::REDUCED),
            (None, Some(si)) => (Material::from_si(si, UnitSystem::NANO), UnitSystem::NANO),
            _ => {
                return Err(CalibrateError::InvalidConfig(
                    "give exactly one of [material] (engine units), [material_si] (SI) and \
                     [material_card] (an MD card, read by CalibrationConfig::from_file)"
                        .into(),
                ))
            }
        };
        refuse_unreachable(&target, self.law)?;
        let material = target.clone();
        self.solver.validate()?;
        let mut model = match self.law {
            ForceLaw::Cohesive => PairModel::cohesive(material),
            ForceLaw::NormalOnly => PairModel::normal_only(material),
        };
        let design = design_poisson_ratio(&model);
        if let Some(nu_d) = design {
            // Keep k_N at its closed-form value and start from a small tangential stiffness and cap.
            let an = |nu: f64| 1.0 / (1.0 - 2.0 * nu);
            let ratio = an(model.material.poisson_ratio) / an(nu_d);
            model.material.poisson_ratio = nu_d;
            model.scale = ParamScale {
                k_n: self.start.k_n * ratio,
                k_t: self.start.k_t * DESIGN_TANGENTIAL_START,
                f_mt: self.start.f_mt * DESIGN_TANGENTIAL_START,
                ..self.start
            };
        } else {
            model.scale = self.start;
        }
        model.validate()?;
        let unknowns = self.unknowns.clone().unwrap_or_else(|| match self.law {
            ForceLaw::Cohesive => Unknown::ALL.to_vec(),
            ForceLaw::NormalOnly => vec![Unknown::KN, Unknown::DeltaE, Unknown::DeltaF],
        });
        if unknowns.is_empty() || self.targets.is_empty() {
            return Err(CalibrateError::InvalidConfig(
                "at least one unknown and one target".into(),
            ));
        }
        // A repeated target would weigh its residual twice, a repeated unknown make the Jacobian
        // rank-deficient: both are typing slips, refused rather than silently used.
        if let Some(t) = first_repeat(&self.targets) {
            return Err(CalibrateError::InvalidConfig(format!(
                "target {} is listed twice",
                t.name()
            )));
        }
        if let Some(u) = first_repeat(&unknowns) {
            return Err(CalibrateError::InvalidConfig(format!(
                "unknown {} is listed twice",
                u.name()
            )));
        }
        if self.law == ForceLaw::NormalOnly {
            if let Some(u) = unknowns
                .iter()
                .find(|u| matches!(u, Unknown::KT | Unknown::FMt))
            {
                return Err(CalibrateError::InvalidConfig(format!(
                    "{} has no effect with the normal-only law (no tangential force)",
                    u.name()
                )));
            }
        }
        let mut sample = self.sample.clone();
        if let Some(d0) = self.d0_m {
            let d0 = units.length_from_m(d0);
            match &mut sample {
                SampleSpec::Hcp { d0_over_dc, .. }
                | SampleSpec::Amorphous { d0_over_dc, .. }
                | SampleSpec::HexMonolayer { d0_over_dc, .. } => {
                    *d0_over_dc = d0 / model.material.critical_diameter()
                }
                SampleSpec::File { .. } => {
                    return Err(CalibrateError::InvalidConfig(
                        "d0_m needs a generated sample, not a file".into(),
                    ))
                }
            }
        }
        let d0 = match &sample {
            SampleSpec::Hcp { d0_over_dc, .. }
            | SampleSpec::Amorphous { d0_over_dc, .. }
            | SampleSpec::HexMonolayer { d0_over_dc, .. } => {
                Some(d0_over_dc * model.material.critical_diameter())
            }
            SampleSpec::File { .. } => None,
        };
        let seeds = match (sample.seed(), &self.recipe.seeds) {
            (None, _) => Vec::new(),
            (Some(_), Some(list)) => list.clone(),
            (Some(s), None) => vec![s, s + 1, s + 2],
        };
        if sample.seed().is_some() && seeds.is_empty() {
            return Err(CalibrateError::InvalidConfig(
                "[recipe] seeds must name at least one seed".into(),
            ));
        }
        if let Some(v) = self
            .verification
            .samples
            .iter()
            .find(|v| v.length == 1.0 && v.width == 1.0 && seeds.contains(&v.seed))
        {
            return Err(CalibrateError::InvalidConfig(format!(
                "verification seed {} is also a calibration seed: the card must be verified on \
                 samples the calibration never saw",
                v.seed
            )));
        }
        for v in &self.verification.samples {
            sample.with_seed(v.seed).resized(v.length, v.width)?;
        }
        let samples = recipe_samples(&sample, &seeds);
        let mut tests = self.tests;
        if self.targets.contains(&Target::SurfaceEnergy) {
            // The surface energy needs the separated state (strength tests stop early otherwise).
            tests.tensile.post_peak_strain = tests.tensile.post_peak_strain.max(0.3);
        }
        Ok(Prepared {
            model,
            target,
            design_poisson_ratio: design,
            units,
            sample,
            samples,
            seeds,
            d0,
            targets: self.targets.clone(),
            unknowns,
            tests,
        })
    }
}

/// Refuses Poisson's ratios the force law cannot represent, whatever the multipliers (paper 000
/// section 2.2: A_T of eq 16 is negative above 1/4; paper 004: the normal-only law gives 1/4).
pub fn refuse_unreachable(m: &Material, law: ForceLaw) -> Result<()> {
    let nu = m.poisson_ratio;
    let impossible = match law {
        ForceLaw::Cohesive => nu > 0.25,
        ForceLaw::NormalOnly => (nu - 0.25).abs() > 1e-9,
    };
    match m.validate(law) {
        Err(e) if impossible => Err(CalibrateError::Unreachable(format!(
            "{e}. Calibration only rescales k_N, k_T, delta_e, delta_f and F_mT; it cannot move \
             the Poisson's ratio outside what the force law spans ({}), so no simulation was run",
            match law {
                ForceLaw::Cohesive => "nu <= 1/4 with tangential forces",
                ForceLaw::NormalOnly => "nu = 1/4 exactly without them",
            }
        ))),
        Err(e) => Err(e.into()),
        Ok(()) => Ok(()),
    }
}

/// Multiplier on the design-nu k_T and F_mT at the start: k_T / k_N = 0.05, small like the closed form's 0.
const DESIGN_TANGENTIAL_START: f64 = 0.3;

/// Near nu = 1/4 the closed form (eq 16) gives A_T -> 0, so k_T and F_mT vanish and no multiplier can
/// bring them back, while a lattice without tangential forces has nu above 1/4 (0.277 for HCP): the
/// target is then out of reach of the multipliers. For targets with (1 - 4 nu) / (1 + nu) < 0.05
/// (nu > 0.238) the area coefficients are computed at a design Poisson's ratio of 0.2 instead, with the
/// k_N multiplier set so that the start keeps the closed-form k_N and small k_T, F_mT multipliers. The
/// card then holds the design value in `model.material.poisson_ratio` (what rebuilds the pair
/// parameters) and the target in `targets`.
pub fn design_poisson_ratio(model: &PairModel) -> Option<f64> {
    let nu = model.material.poisson_ratio;
    (model.law == ForceLaw::Cohesive && (1.0 - 4.0 * nu) / (1.0 + nu) < 0.05).then_some(0.2)
}

/// The first element that appears again later in `v`.
fn first_repeat<T: PartialEq + Copy>(v: &[T]) -> Option<T> {
    v.iter()
        .enumerate()
        .find(|&(k, x)| v[k + 1..].contains(x))
        .map(|(_, &x)| x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_si_card_gets_the_silica_recipe_on_thick_samples_and_keeps_its_own_exponent() {
        let mut md = SiMaterial::table5();
        md.scaling = None;
        let cfg = CalibrationConfig::si_card(md.clone()).unwrap();
        let base = CalibrationConfig::from_toml(SILICA).unwrap();
        // The recipe's exponent for a card without one; everything else of the card as given.
        let m = cfg.material_si.clone().unwrap();
        assert_eq!(m.scaling, base.material_si.as_ref().unwrap().scaling);
        assert_eq!(m.young_modulus, md.young_modulus);
        assert_eq!(cfg.recipe.seeds, Some((1..=SI_SEEDS).collect()));
        let SampleSpec::Amorphous {
            l_over_d0,
            w_over_d0,
            ..
        } = cfg.sample
        else {
            panic!("the silica recipe is amorphous")
        };
        assert_eq!(w_over_d0, SI_THICKNESS);
        let SampleSpec::Amorphous { l_over_d0: l0, .. } = base.sample else {
            unreachable!()
        };
        assert_eq!(l_over_d0, l0, "the edge stays the recipe's");
        assert_eq!(
            (cfg.solver, cfg.unknowns.clone()),
            (base.solver, base.unknowns)
        );
        md.scaling = Some(0.25);
        let own = CalibrationConfig::si_card(md).unwrap();
        assert_eq!(own.material_si.unwrap().scaling, Some(0.25));
    }

    #[test]
    fn sample_size_sets_what_is_given_and_leaves_a_file_alone() {
        let mut cfg = CalibrationConfig::table4_hcp(0.15, 8.0);
        cfg.set_sample_size(Some(10.0), None);
        assert!(matches!(
            cfg.sample,
            SampleSpec::Hcp { l_over_d0, w_over_d0, .. } if l_over_d0 == 10.0 && w_over_d0 == 3.0
        ));
        cfg.sample = SampleSpec::File {
            path: "s.json".into(),
        };
        cfg.set_sample_size(Some(4.0), Some(4.0));
        assert!(matches!(cfg.sample, SampleSpec::File { .. }));
    }

    #[test]
    fn a_typed_config_has_the_defaults_a_toml_file_gets() {
        let from_file = CalibrationConfig::from_toml(
            "[material]\nyoung_modulus = 1.0\npoisson_ratio = 0.15\ntensile_strength = 0.2\n\
             shear_strength = 0.1\nsurface_energy = 1.5\nrestitution = 0.95\ndensity = 1.0\n\
             [sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = 8.0\nw_over_d0 = 3.0\n\
             [solver]\nmax_iterations = 12\n",
        )
        .unwrap();
        assert_eq!(CalibrationConfig::table4_hcp(0.15, 8.0), from_file);
        let mut other = CalibrationConfig::table4_hcp(0.15, 8.0);
        other.solver.max_iterations = Settings::default().max_iterations;
        assert_eq!(
            other,
            CalibrationConfig::new(Material::table4(0.15), from_file.sample.clone())
        );
    }
}
