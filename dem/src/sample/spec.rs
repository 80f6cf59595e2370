//! Sample recipes: what a scenario asks for (an HCP lattice, a relaxed amorphous solid of a size
//! distribution, or a saved file), sizes in units of d0 and d0 in units of d_c (eq 18), built by
//! [`make_sample`]. Patch tests, calibrations and the wear scenarios all start from one.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::insert::{random_insertion, InsertionConfig};
use super::relax::relax_resumable;
use super::{RelaxConfig, Sample, SizeDistribution};
use crate::error::{DemError, Result};
use crate::io::progress::ProgressFile;
use crate::material::PairModel;
use crate::sim::Parallelism;
use crate::Vec3;

/// Which sample the tests run on; sizes in units of d0 (and d0 in units of d_c, eq 18).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind", deny_unknown_fields)]
pub enum SampleSpec {
    /// HCP lattice of L x L x W (paper 000 section 3.1: L = 25 d0, W = 3 d0).
    Hcp {
        d0_over_dc: f64,
        l_over_d0: f64,
        w_over_d0: f64,
    },
    /// Relaxed amorphous sample (section 3.2: L = 100 d0, W = 3 d0, d in [0.75, 1.25] d0). `dl_over_l`
    /// fixes the largest diameter to a fraction of L instead (section 3.3 / A.4: 0.05).
    /// `insert_fraction` is the volume fraction of the random insertion (default 0.75, the paper's); a
    /// lower one (0.5) leaves holes in the relaxed solid (docs/patch-tests.md, looser packings).
    /// `h_over_d0` gives the box a height (y) other than L (the junction's 60 x 40 x 40 nm box).
    Amorphous {
        d0_over_dc: f64,
        l_over_d0: f64,
        w_over_d0: f64,
        // Not written when absent, so earlier recipes keep their fingerprints.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        h_over_d0: Option<f64>,
        #[serde(default = "d_ds")]
        ds_over_d0: f64,
        #[serde(default = "d_dl")]
        dl_over_d0: f64,
        #[serde(default)]
        dl_over_l: Option<f64>,
        #[serde(default = "d_seed")]
        seed: u64,
        // Not written when it is the default, so configurations (and calibration fingerprints) made
        // before this field existed serialise as before.
        #[serde(default = "d_insert", skip_serializing_if = "is_d_insert")]
        insert_fraction: f64,
    },
    /// A quasi-2D hex monolayer (`sample::monolayer`) of about L x H in the x-y plane, W thick along z,
    /// diameters d0 (1 + p u), relaxed in the plane; run it with `RunConfig::planar`.
    HexMonolayer {
        d0_over_dc: f64,
        l_over_d0: f64,
        h_over_d0: f64,
        w_over_d0: f64,
        polydispersity: f64,
        seed: u64,
    },
    /// A sample saved by `cgdem sample` or [`Sample::save`].
    File { path: PathBuf },
}

fn d_ds() -> f64 {
    0.75
}
fn d_dl() -> f64 {
    1.25
}
fn d_seed() -> u64 {
    1
}
fn d_insert() -> f64 {
    0.75
}
fn is_d_insert(v: &f64) -> bool {
    *v == d_insert()
}

/// Builds the sample of `spec` for `model` (amorphous samples are relaxed with `relax`).
pub fn make_sample(
    spec: &SampleSpec,
    model: &PairModel,
    relax: &RelaxConfig,
    par: Parallelism,
) -> Result<Sample> {
    make_sample_resumable(spec, model, relax, par, None)
}

/// [`make_sample`], with the relaxation of an amorphous sample keeping its progress in `progress`
/// (see [`relax_resumable`]; insertion is quick and deterministic, so it is simply redone).
pub fn make_sample_resumable(
    spec: &SampleSpec,
    model: &PairModel,
    relax: &RelaxConfig,
    par: Parallelism,
    progress: Option<&ProgressFile>,
) -> Result<Sample> {
    let d_c = model.material.critical_diameter();
    let rho = model.material.density;
    match spec {
        SampleSpec::Hcp {
            d0_over_dc,
            l_over_d0,
            w_over_d0,
        } => {
            let d0 = d0_over_dc * d_c;
            Sample::hcp(
                Vec3::new(l_over_d0 * d0, l_over_d0 * d0, w_over_d0 * d0),
                d0,
                rho,
            )
        }
        SampleSpec::Amorphous {
            d0_over_dc,
            l_over_d0,
            w_over_d0,
            h_over_d0,
            ds_over_d0,
            dl_over_d0,
            dl_over_l,
            seed,
            insert_fraction,
        } => {
            let d0 = d0_over_dc * d_c;
            let l = l_over_d0 * d0;
            let dl = dl_over_l.map_or(dl_over_d0 * d0, |f| (f * l).max(d0));
            let ins = InsertionConfig {
                lengths: Vec3::new(l, h_over_d0.map_or(l, |h| h * d0), w_over_d0 * d0),
                sizes: SizeDistribution::paper000(d0, ds_over_d0 * d0, dl),
                volume_fraction: *insert_fraction,
                density: rho,
                seed: *seed,
            };
            relax_resumable(&random_insertion(&ins)?, model, relax, par, progress)
        }
        SampleSpec::HexMonolayer {
            d0_over_dc,
            l_over_d0,
            h_over_d0,
            w_over_d0,
            polydispersity,
            seed,
        } => {
            let d0 = d0_over_dc * d_c;
            let raw = super::monolayer::hex_monolayer(
                l_over_d0 * d0,
                h_over_d0 * d0,
                d0,
                w_over_d0 * d0,
                rho,
                *polydispersity,
                *seed,
            )?;
            super::monolayer::relax_planar(&raw, model, par)
        }
        SampleSpec::File { path } => Sample::load(path),
    }
}

impl SampleSpec {
    /// The same recipe with d0 = `v` d_c (a point of a d0 sweep); a saved file has no d0 to change.
    pub fn with_d0(&self, v: f64) -> Result<SampleSpec> {
        let mut s = self.clone();
        match &mut s {
            SampleSpec::Hcp { d0_over_dc, .. }
            | SampleSpec::Amorphous { d0_over_dc, .. }
            | SampleSpec::HexMonolayer { d0_over_dc, .. } => *d0_over_dc = v,
            SampleSpec::File { .. } => {
                return Err(DemError::InvalidConfig(
                    "a d0 sweep needs a generated sample, not a file".into(),
                ))
            }
        }
        Ok(s)
    }

    /// The same recipe drawn with another seed (an HCP lattice or a saved file has none: unchanged).
    pub fn with_seed(&self, v: u64) -> SampleSpec {
        let mut s = self.clone();
        if let SampleSpec::Amorphous { seed, .. } | SampleSpec::HexMonolayer { seed, .. } = &mut s {
            *seed = v;
        }
        s
    }

    /// The seed of an amorphous recipe.
    pub fn seed(&self) -> Option<u64> {
        match self {
            SampleSpec::Amorphous { seed, .. } | SampleSpec::HexMonolayer { seed, .. } => {
                Some(*seed)
            }
            _ => None,
        }
    }

    /// The same recipe with the in-plane edge L and the thickness W multiplied by `length` and
    /// `width` (a larger sample of the same material and discretisation); a saved file cannot grow.
    pub fn resized(&self, length: f64, width: f64) -> Result<SampleSpec> {
        if !(length.is_finite() && length > 0.0 && width.is_finite() && width > 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "sample size factors must be positive (length {length}, width {width})"
            )));
        }
        let mut s = self.clone();
        match &mut s {
            SampleSpec::Hcp {
                l_over_d0,
                w_over_d0,
                ..
            }
            | SampleSpec::Amorphous {
                l_over_d0,
                w_over_d0,
                ..
            } => {
                *l_over_d0 *= length;
                *w_over_d0 *= width;
            }
            SampleSpec::HexMonolayer {
                l_over_d0,
                h_over_d0,
                w_over_d0,
                ..
            } => {
                *l_over_d0 *= length;
                *h_over_d0 *= length;
                *w_over_d0 *= width;
            }
            SampleSpec::File { .. } if length == 1.0 && width == 1.0 => {}
            SampleSpec::File { .. } => {
                return Err(DemError::InvalidConfig(
                    "a saved sample cannot be resized; give a generated recipe".into(),
                ))
            }
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insert_fraction_defaults_to_the_papers_and_is_not_written_then() {
        let json =
            r#"{"kind": "amorphous", "d0_over_dc": 0.6, "l_over_d0": 10.0, "w_over_d0": 3.0}"#;
        let spec: SampleSpec = serde_json::from_str(json).unwrap();
        match &spec {
            SampleSpec::Amorphous {
                insert_fraction, ..
            } => assert_eq!(*insert_fraction, 0.75),
            _ => panic!("{spec:?}"),
        }
        // The default is not serialised, so older configurations keep their fingerprints.
        assert!(!serde_json::to_string(&spec)
            .unwrap()
            .contains("insert_fraction"));
        let loose = r#"{"kind": "amorphous", "d0_over_dc": 0.6, "l_over_d0": 10.0, "w_over_d0": 3.0,
                        "insert_fraction": 0.5}"#;
        let spec: SampleSpec = serde_json::from_str(loose).unwrap();
        assert!(serde_json::to_string(&spec)
            .unwrap()
            .contains("\"insert_fraction\":0.5"));
    }

    #[test]
    fn seeds_and_sizes_change_only_what_they_name() {
        let json =
            r#"{"kind": "amorphous", "d0_over_dc": 0.6, "l_over_d0": 10.0, "w_over_d0": 3.0}"#;
        let spec: SampleSpec = serde_json::from_str(json).unwrap();
        assert_eq!(spec.seed(), Some(1));
        let other = spec.with_seed(7).resized(1.0, 2.0).unwrap();
        match other {
            SampleSpec::Amorphous {
                seed,
                l_over_d0,
                w_over_d0,
                d0_over_dc,
                ..
            } => assert_eq!(
                (seed, l_over_d0, w_over_d0, d0_over_dc),
                (7, 10.0, 6.0, 0.6)
            ),
            _ => panic!(),
        }
        assert!(spec.resized(0.0, 1.0).is_err());
        let file = SampleSpec::File {
            path: "s.json".into(),
        };
        assert_eq!(file.with_seed(3), file);
        assert!(file.resized(2.0, 1.0).is_err() && file.resized(1.0, 1.0).is_ok());
    }
}
