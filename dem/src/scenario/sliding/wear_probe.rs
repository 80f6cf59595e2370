//! The wear particles of a sliding run (paper 004 Fig. 3a and 3c): at the end of every profile window,
//! the loose clusters of the layer between that window's end and the previous one's
//! ([`wear::tbl::wear_particles`]: bonds that persist over the window, clusters of them that hold no
//! body particle).
//!
//! Bonds: pairs within r_i + r_j + delta_f(d0 pair), the cohesive reach of a nominal pair, as the
//! junction's cluster analysis counts them. The interval is one window, which in every shipped config
//! spans a slide of 5 d0 or more (the module docs of `wear::tbl::wear_particles` say why it must span
//! a few).

use serde::{Deserialize, Serialize};
use wear::outcome::Bonding;
use wear::tbl::{wear_particles, LayerGeometry, WearParticles};

use super::run::slide;
use crate::error::{DemError, Result};
use crate::observe::{periodicity, unwrapped, Observer};
use crate::sim::Simulation;
use crate::state::sphere_volume;

/// The wear particles at the end of one window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WearRecord {
    /// Last step of the window and the top body's slide by then.
    pub step: u64,
    pub slide: f64,
    #[serde(flatten)]
    pub particles: WearParticles,
}

/// The observer (its state is checkpointed with the run's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct WearProbe {
    every: u64,
    /// Bond reach beyond the two radii.
    margin: f64,
    layer: Vec<usize>,
    bodies: Vec<usize>,
    volume_fraction: f64,
    thickness: f64,
    min_members: usize,
    v0: f64,
    ramp: Option<f64>,
    /// Unwrapped positions at the previous window's end (the start, for the first window).
    previous: Vec<[f64; 3]>,
    pub records: Vec<WearRecord>,
}

/// What the probe needs to know of the run.
pub(super) struct WearProbeSpec {
    pub every: u64,
    pub margin: f64,
    pub free: Vec<bool>,
    pub volume_fraction: f64,
    pub min_members: usize,
    pub v0: f64,
    pub ramp: Option<f64>,
}

impl WearProbe {
    /// Starts from `sim` now.
    pub fn new(sim: &Simulation, spec: WearProbeSpec) -> Result<Self> {
        let (layer, bodies): (Vec<usize>, Vec<usize>) =
            (0..spec.free.len()).partition(|&i| spec.free[i]);
        if layer.is_empty() || bodies.is_empty() {
            return Err(DemError::InvalidConfig(format!(
                "sliding wear particles: a layer of {} particles between bodies of {}",
                layer.len(),
                bodies.len()
            )));
        }
        Ok(WearProbe {
            every: spec.every,
            margin: spec.margin,
            layer,
            bodies,
            volume_fraction: spec.volume_fraction,
            thickness: sim.sim_box.lengths().z,
            min_members: spec.min_members,
            v0: spec.v0,
            ramp: spec.ramp,
            previous: unwrapped(sim),
            records: Vec::new(),
        })
    }
}

impl Observer for WearProbe {
    fn every(&self) -> u64 {
        self.every
    }

    fn observe(&mut self, sim: &Simulation) -> Result<()> {
        let now = unwrapped(sim);
        let radius = &sim.particles.radius;
        let volume: Vec<f64> = radius.iter().map(|&r| sphere_volume(r)).collect();
        let bonding = Bonding {
            radii: Some(radius.clone()),
            margin: self.margin,
            periodicity: periodicity(&sim.sim_box),
        };
        let geometry = LayerGeometry {
            volume: &volume,
            volume_fraction: self.volume_fraction,
            thickness: self.thickness,
        };
        let particles = wear_particles(
            &self.previous,
            &now,
            &bonding,
            &self.layer,
            &self.bodies,
            &geometry,
            self.min_members,
        )
        .map_err(|e| DemError::InvalidConfig(format!("sliding wear particles: {e}")))?;
        self.records.push(WearRecord {
            step: sim.step_count(),
            slide: slide(self.v0, self.ramp, sim.time()),
            particles,
        });
        self.previous = now;
        Ok(())
    }
}

/// The wear particles over a run, lengths over L.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WearSummary {
    /// Mean count of wear particles and mean detached fraction of the layer over the steady windows.
    pub steady_count: f64,
    pub steady_detached: f64,
    /// The largest wear particle's equivalent diameter over L (0 in a window without one): mean over
    /// the steady windows, the largest over the run and the slide over L at which it was, and at the
    /// end of the run. Fig. 3c's particles grow "until reaching the size of the system", 1.
    pub steady_largest_over_l: f64,
    pub max_largest_over_l: f64,
    pub max_at_l: f64,
    pub final_largest_over_l: f64,
}

impl WearSummary {
    /// From the `records` of a run, the steady ones those for which `steady` holds, with wear
    /// particles of at least `min_members` and the system size `length`. None without records.
    pub fn of(
        records: &[WearRecord],
        steady: impl Fn(&WearRecord) -> bool,
        min_members: usize,
        length: f64,
    ) -> Option<Self> {
        let size = |r: &WearRecord| r.particles.wear_particle_diameter(min_members) / length;
        let last = records.last()?;
        let st: Vec<&WearRecord> = records.iter().filter(|r| steady(r)).collect();
        let mean = |f: &dyn Fn(&WearRecord) -> f64| {
            st.iter().map(|r| f(r)).sum::<f64>() / st.len().max(1) as f64
        };
        // The first window of the largest size (ties: the earlier).
        let top = records
            .iter()
            .fold(None::<&WearRecord>, |best, r| match best {
                Some(b) if size(b) >= size(r) => Some(b),
                _ => Some(r),
            })?;
        Some(WearSummary {
            steady_count: mean(&|r| r.particles.count as f64),
            steady_detached: mean(&|r| r.particles.detached),
            steady_largest_over_l: mean(&size),
            max_largest_over_l: size(top),
            max_at_l: top.slide / length,
            final_largest_over_l: size(last),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(step: u64, count: usize, largest: usize, diameter: f64) -> WearRecord {
        WearRecord {
            step,
            slide: step as f64 / 10.0,
            particles: WearParticles {
                detached: count as f64 / 100.0,
                count,
                largest,
                largest_fraction: largest as f64 / 100.0,
                largest_diameter: diameter,
            },
        }
    }

    #[test]
    fn the_summary_reads_sizes_of_wear_particles_only_and_finds_the_largest() {
        let r = [
            rec(10, 0, 3, 0.5),  // crumbs only: size 0
            rec(20, 2, 40, 4.0), // the largest
            rec(30, 1, 40, 4.0), // as large, later
            rec(40, 1, 12, 2.0),
        ];
        let s = WearSummary::of(&r, |w| w.step >= 30, 10, 8.0).unwrap();
        assert_eq!(s.max_largest_over_l, 0.5);
        assert_eq!(s.max_at_l, 2.0 / 8.0);
        assert_eq!(s.final_largest_over_l, 0.25);
        assert_eq!(s.steady_count, 1.0);
        assert_eq!(s.steady_largest_over_l, (0.5 + 0.25) / 2.0);
        assert_eq!(s.steady_detached, 0.01);
        assert!(WearSummary::of(&[], |_| true, 10, 1.0).is_none());
        // A threshold above every cluster: no wear particle anywhere.
        let s = WearSummary::of(&r, |_| true, 50, 8.0).unwrap();
        assert_eq!((s.max_largest_over_l, s.final_largest_over_l), (0.0, 0.0));
    }
}
