//! Junction shear (paper 000 section 4, Figs. 9-10 and A.10): two solids joined by one cylindrical
//! junction, sheared until the junction either smooths plastically or detaches as a rolling wear
//! particle. Junctions smaller than the critical size d* (eq 22) smooth, larger ones detach.
//!
//! Set-up, every length configurable (defaults: the paper's silica runs, in nm with
//! [`crate::units::UnitSystem::NANO`]):
//! - a relaxed amorphous box of `lengths` (x: sliding, y: normal, z: width; 60 x 40 x 40 nm) of the
//!   size distribution d in [d_s, d_l] around d0 (d_s = 0.75 d0, d_l = 7.5 nm);
//! - carved into two solids by removing the slab of height H = D/2 around the box's mid-height, except
//!   a cylinder of diameter D whose axis is the normal (y) through the box centre: the junction;
//! - rigid walls of the particles within 1.5 d0 of the outer faces; the bottom one fixed, the top one
//!   driven at constant velocity along x (10 m/s) under a constant normal pressure (100 MPa, traction
//!   times the box cross-section); periodic along x and z;
//! - dt = 0.1 dt_c (eq 6), the pair dampers only (eta of the material), for `duration` (10 ns).
//!
//! Decision (the junction's shape): the paper gives a "cylindrical junction of diameter D and height
//! H = D/2" between two solids, and its figures are side views of a junction that rolls about the
//! width. Two cylinders fit the words: one lying along the width z (`shape = "ridge"`, the default:
//! the barrel of it that bridges the gap spans the periodic width, the 3D extrusion of the
//! quasi-2D junctions of the MD studies the paper reproduces), and one standing along the normal y
//! (`shape = "column"`, a disc-shaped contact of height H). Measured (docs/junction.md, "The
//! junction's shape"), closed-form Table 5 silica, the paper's box and load: the ridge reproduces
//! the paper, D = 20 nm rolls off as a wear particle at d0 = 1.5, 3 and 6 nm and D = 10 nm smooths
//! (two seeds of three at 3 nm); the column smooths at both sizes and every d0 (18 runs; why is not
//! measured, docs/junction.md gives a reading). So the ridge is the default; the column stays for
//! comparison. A wear particle rolls about z in either, which is what the classifier measures
//! (rotation in the x-y plane).
//!
//! Decision (the smallest junction): paper 000 shears D = 10 nm at d0 = 6 nm, i.e. D = 1.67 d0, so the
//! geometry accepts D down to 1.5 d0 (`min_diameter_over_d0`); below that the junction is a particle or
//! two and its outcome says nothing about the material.
//!
//! Quasi-2D variant (`monolayer`, issue 17: the DEM side of the comparison with the 2D MD model
//! material): the box is a hex monolayer in the x-y plane (`SampleSpec::HexMonolayer`, relaxed in the
//! plane), run with `RunConfig::planar`; the column (the cylinder about y, `shape = "column"`, which a
//! monolayer requires) then cuts the layer in a strip of width D, the MD junction's shape
//! (`md-bridge::junction`). `pressure` is then a force per unit length of
//! the wall (a 2D stress, as the MD `normal_pressure`): the wall's traction is pressure / L_z. The
//! layer's thickness L_z only keeps particles clear of their own images; the periodic width check
//! applies to x alone. Why a monolayer: `scenario::monolayer`.
//!
//! Outcome: the members (particles whose centres lie in the junction) are recorded every
//! `duration / frames`; [`wear::classify`] decides from their rigid rotation, with the tangential force
//! on the top wall and the cluster analysis of [`wear::outcome::detachment`] as evidence.

mod geometry;
mod run;

use serde::{Deserialize, Serialize};
use wear::ClassifyParams;

use crate::error::{DemError, Result};
use crate::sample::RelaxConfig;

pub use crate::scenario::driven::Snapshot;
pub use geometry::{build, Geometry, BODY_LOWER, BODY_UPPER};
pub use run::{run, run_resumable, JunctionResult};

/// Which cylinder of diameter D joins the two solids (module docs, decision on the junction's shape).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JunctionShape {
    /// A cylinder lying along the width z, cut by the gap: a ridge across the periodic width.
    #[default]
    Ridge,
    /// A cylinder standing along the normal y: a disc-shaped contact, a column of height H.
    Column,
}

impl JunctionShape {
    /// The cylinder's axis.
    pub fn axis(self) -> crate::Vec3 {
        match self {
            JunctionShape::Ridge => crate::Vec3::z(),
            JunctionShape::Column => crate::Vec3::y(),
        }
    }
}

/// A junction shear run, in the engine's length, time and stress units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct JunctionConfig {
    /// Box edge lengths (x sliding, y normal, z width); default 60 x 40 x 40 (nm, paper 000 section 4).
    pub lengths: [f64; 3],
    /// Junction diameter D; default 20 (nm), the paper's detaching junction.
    pub diameter: f64,
    /// The junction's cylinder; default the ridge along the width (module docs: it reproduces the
    /// paper's outcomes, the column does not). Always written, so that runs of the two shapes, and runs
    /// classified before the cluster analysis followed periodic images, never share a cache key.
    pub shape: JunctionShape,
    /// Junction height over D; default 0.5 (H = D/2, paper).
    pub height_over_diameter: f64,
    /// Nominal particle diameter d0; default 6 (nm), the paper's coarsest discretisation.
    pub d0: f64,
    /// Smallest diameter over d0; default 0.75 (paper: d_s = 0.75 d0).
    pub ds_over_d0: f64,
    /// Largest diameter d_l; default 7.5 (nm, paper: fixed for every d0 so that all discretisations
    /// have the same properties).
    pub dl: f64,
    /// Seed of the random insertion: one relaxed sample per seed; default 1.
    pub seed: u64,
    /// Volume fraction of the random insertion; default 0.75 (paper 000 section 3.2).
    pub insert_fraction: f64,
    /// Relaxation of the sample; default the paper's (section 3.2).
    pub relax: RelaxConfig,
    /// Wall thickness over d0; default 1.5 (paper).
    pub wall_thickness_over_d0: f64,
    /// Top-wall velocity along x; default 10 (m/s = nm/ns; paper, 0.2 % of sqrt(E/rho)).
    pub velocity: f64,
    /// Normal pressure on the top wall; default 100 (MPa, paper).
    pub pressure: f64,
    /// Sliding time; default 10 (ns, paper Table 6: 100 nm of sliding, five junction diameters).
    pub duration: f64,
    /// Time step over dt_c (eq 6); default 0.1 (paper).
    pub time_step_fraction: f64,
    /// Neighbour skin over the median diameter; default 0.2, not the engine's 0.05: a sheared junction
    /// rattles (some particles move ~100 m/s), so at 0.05 the d0 = 1.5 nm run rebuilt its list every
    /// 13 steps and spent half its time there (28.7 s of shear run against 14.0 s at 0.2, 14.3 s at
    /// 0.3, 19.2 s at 0.5; docs/performance.md). The skin changes only which zero-force pairs the list
    /// holds, so results agree to round-off (dem/tests/junction.rs).
    pub skin_fraction: f64,
    /// Member frames recorded over the run; default 100 (a rolling particle turns ~0.05 rad between
    /// two, far below the pi a frame-to-frame fit could confuse).
    pub frames: u64,
    /// Top-wall force samples over the run; default 1000.
    pub force_samples: u64,
    /// Dump frames over the run (0: none); default 50 (a film in OVITO, ~100 kB per frame at d0 = 6).
    pub dump_frames: u64,
    /// Outcome thresholds; default the classifier's.
    pub classify: ClassifyParams,
    /// Smallest D / d0 accepted; default 1.5 (see the module docs).
    pub min_diameter_over_d0: f64,
    /// The run stops as a collapse ([`crate::DemError::MaterialCollapsed`]) once the top wall has
    /// descended by more than this many junction heights H; default 1. A junction squashed flat
    /// lowers the wall by less than H (its volume spread over the interface is a 1.3 nm layer at the
    /// paper's D = 20 nm), so a larger descent means the solids themselves are compacting: measured
    /// with calibrated silica cards whose relaxed packings interpenetrate (docs/junction.md,
    /// "Calibrated cards collapse under shear"), where the walls met; closed-form runs descend by
    /// 0.28-0.73 H.
    /// Not written when it is the default, so the keys of earlier runs stay.
    #[serde(skip_serializing_if = "is_one")]
    pub max_descent_over_height: f64,
    /// The quasi-2D monolayer variant (module docs); default none: the 3D amorphous box. Not written
    /// when absent, so the keys of earlier runs and samples stay.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub monolayer: Option<Monolayer>,
}

/// The layer of a quasi-2D junction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Monolayer {
    /// Layer thickness L_z over d0 (the periodic length along z; 2D forces are per this length);
    /// default 2.5, above twice the largest diameter so that no particle meets its own image.
    pub thickness_over_d0: f64,
    /// Polydispersity p of the layer (diameters d0 (1 + p u), u uniform in [-1, 1] per seed); default
    /// 0.005: enough for the seeds to differ (the MD seeds draw thermal velocities; a DEM run starts at
    /// rest), small enough to keep the hex layer's constants (measured on 40 sigma layers at d0 = 2
    /// sigma: nu_2D 0.3333, E_2D -0.3 %, tensile strength -8 %, which `tensile_correction` of the
    /// material restores; p = 0.02 costs 32 % of the strength, docs/junction.md).
    pub polydispersity: f64,
}

impl Default for Monolayer {
    fn default() -> Self {
        Monolayer {
            thickness_over_d0: 2.5,
            polydispersity: 0.005,
        }
    }
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

impl Default for JunctionConfig {
    fn default() -> Self {
        JunctionConfig {
            lengths: [60.0, 40.0, 40.0],
            diameter: 20.0,
            shape: JunctionShape::Ridge,
            height_over_diameter: 0.5,
            d0: 6.0,
            ds_over_d0: 0.75,
            dl: 7.5,
            seed: 1,
            insert_fraction: 0.75,
            relax: RelaxConfig::default(),
            wall_thickness_over_d0: 1.5,
            velocity: 10.0,
            pressure: 100.0,
            duration: 10.0,
            time_step_fraction: 0.1,
            skin_fraction: 0.2,
            frames: 100,
            force_samples: 1000,
            dump_frames: 50,
            classify: ClassifyParams::default(),
            min_diameter_over_d0: 1.5,
            max_descent_over_height: 1.0,
            monolayer: None,
        }
    }
}

impl JunctionConfig {
    /// Junction height H.
    pub fn height(&self) -> f64 {
        self.height_over_diameter * self.diameter
    }

    /// Wall thickness.
    pub fn wall_thickness(&self) -> f64 {
        self.wall_thickness_over_d0 * self.d0
    }

    /// Checks everything that does not need the sample: positive numbers, a junction that fits the
    /// box and the discretisation, walls clear of the junction.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(DemError::InvalidConfig(format!("junction: {m}")));
        let positive = [
            ("lengths[0]", self.lengths[0]),
            ("lengths[1]", self.lengths[1]),
            ("lengths[2]", self.lengths[2]),
            ("diameter", self.diameter),
            ("height_over_diameter", self.height_over_diameter),
            ("d0", self.d0),
            ("ds_over_d0", self.ds_over_d0),
            ("dl", self.dl),
            ("insert_fraction", self.insert_fraction),
            ("wall_thickness_over_d0", self.wall_thickness_over_d0),
            ("velocity", self.velocity),
            ("duration", self.duration),
            ("time_step_fraction", self.time_step_fraction),
            ("skin_fraction", self.skin_fraction),
            ("min_diameter_over_d0", self.min_diameter_over_d0),
            ("max_descent_over_height", self.max_descent_over_height),
        ];
        if let Some(m) = crate::error::not_positive(&positive) {
            return bad(m);
        }
        if !(self.pressure.is_finite() && self.pressure >= 0.0) {
            return bad(format!("pressure = {} must be >= 0", self.pressure));
        }
        if self.frames < 2 || self.force_samples < 1 {
            return bad("frames must be >= 2 and force_samples >= 1".into());
        }
        let [lx, ly, lz] = self.lengths;
        let d = self.diameter;
        if let Some(m) = &self.monolayer {
            if !(m.thickness_over_d0 >= 2.0 * (1.0 + m.polydispersity)
                && (0.0..0.5).contains(&m.polydispersity))
            {
                return bad(format!(
                    "monolayer: thickness_over_d0 = {} must be at least twice the largest diameter \
                     over d0 (2 (1 + p)) and polydispersity p = {} in [0, 0.5)",
                    m.thickness_over_d0, m.polydispersity
                ));
            }
        }
        if self.monolayer.is_some() && self.shape != JunctionShape::Column {
            return bad(
                "a monolayer's junction is the MD junction's strip, which the column cuts from the \
                 layer: set shape = \"column\""
                    .into(),
            );
        }
        let across = self.room_across(lx, lz);
        if d >= across {
            return bad(format!(
                "a junction of diameter {d} does not fit the box {lx} x {lz} across the sliding plane \
                 (it must be narrower than the sliding length{}, or it touches its own image)",
                if across == lx { "" } else { " and the width" }
            ));
        }
        if d < self.min_diameter_over_d0 * self.d0 {
            return bad(format!(
                "diameter {d} is below {} d0 = {}: a junction of a particle or two says nothing about \
                 the material (lower d0, or min_diameter_over_d0)",
                self.min_diameter_over_d0,
                self.min_diameter_over_d0 * self.d0
            ));
        }
        if self.dl < self.d0 || self.ds_over_d0 > 1.0 {
            return bad(format!(
                "sizes d_s = {} d0 and d_l = {} must bracket d0 = {}",
                self.ds_over_d0, self.dl, self.d0
            ));
        }
        let solid = 0.5 * (ly - self.height());
        let t = self.wall_thickness();
        if solid < t + 0.5 * self.d0 {
            return bad(format!(
                "the walls would cut the junction: each solid is {solid:.4} thick ((lengths[1] - H) / 2) \
                 but a wall takes {t:.4} and at least half a d0 of free material must separate it from \
                 the junction (a taller box, a smaller D or thinner walls)"
            ));
        }
        Ok(())
    }

    /// The periodic length a junction must stay narrower than to clear its own images, for a box of
    /// sliding length `lx` and width `lz`: a ridge spans the width (and a monolayer's strip the layer),
    /// so only the sliding length has to hold it; a column must fit both.
    pub(super) fn room_across(&self, lx: f64, lz: f64) -> f64 {
        match (self.shape, self.monolayer.is_some()) {
            (JunctionShape::Ridge, _) | (_, true) => lx,
            (JunctionShape::Column, false) => lx.min(lz),
        }
    }

    /// Number of steps for the sliding time at time step `dt`.
    pub fn steps(&self, dt: f64) -> Result<u64> {
        crate::scenario::step_budget("the junction shear (duration)", (self.duration / dt).ceil())
    }
}
