//! Observers: what a scenario records while the engine runs, in the spirit of lumol's `Output` with a
//! frequency. [`Simulation::run_observed`] calls each observer after every step whose count is a
//! multiple of its `every`, so a scenario composes observers instead of writing its own step loop.
//!
//! The recording observers are plain serde data: a scenario's progress file keeps them beside the
//! engine checkpoint, and a resumed run continues their records exactly.
//! - [`MemberFrames`]: unwrapped positions of chosen particles (the junction members the outcome
//!   classifier reads);
//! - [`GroupForce`]: the pair force on a group (a wall) and the group's displacement;
//! - [`Dump`]: LAMMPS-style dump frames that OVITO opens, with integer labels (the initial body).

use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use wear::outcome::{unwrap_frame, Periodicity};

use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::io::dump::append_labeled_frame;
use crate::sim::Simulation;
use crate::Vec3;

/// Something recorded every `every()` steps.
pub trait Observer {
    /// Steps between two observations (at least 1).
    fn every(&self) -> u64;
    /// Whether the observation reads the virial stress (the step before it then computes virials).
    fn wants_virial(&self) -> bool {
        false
    }
    /// Records the state after a step.
    fn observe(&mut self, sim: &Simulation) -> Result<()>;
}

impl Simulation {
    /// Advances `n` steps, calling each observer after every step whose count is a multiple of its
    /// `every()` (step counts are absolute, so a resumed run observes at the same steps).
    pub fn run_observed(&mut self, n: u64, observers: &mut [&mut dyn Observer]) -> Result<()> {
        if let Some(o) = observers.iter().find(|o| o.every() == 0) {
            return Err(DemError::InvalidConfig(format!(
                "an observer with every = 0 ({:?})",
                std::any::type_name_of_val(*o)
            )));
        }
        let end = self.step + n;
        while self.step < end {
            // The next step an observer reads (or the end): the steps before it go to `run` in one
            // call, so a thread pool is entered once per observation instead of once per step
            // (issue 21: ~5 us a step). The same steps in the same order, hence the same bits.
            let due = observers
                .iter()
                .map(|o| (self.step / o.every() + 1) * o.every())
                .min()
                .map_or(end, |d| d.min(end));
            if due - self.step > 1 {
                self.run(due - self.step - 1)?;
            }
            let next = self.step + 1;
            if observers
                .iter()
                .any(|o| o.wants_virial() && next.is_multiple_of(o.every()))
            {
                self.request_virial();
            }
            self.step()?;
            for o in observers.iter_mut() {
                if self.step.is_multiple_of(o.every()) {
                    o.observe(self)?;
                }
            }
        }
        Ok(())
    }
}

/// The periodicity of a box, as the outcome classifier's frames see it.
pub fn periodicity(b: &SimBox) -> Periodicity {
    let l = b.lengths();
    Periodicity(std::array::from_fn(|a| b.periodic[a].then_some(l[a])))
}

/// Every particle's position on its continuous path (unwrapped by the engine's image counts): what a
/// cluster analysis between two frames follows each bond's periodic image with.
pub fn unwrapped(sim: &Simulation) -> Vec<[f64; 3]> {
    (0..sim.particles.len())
        .map(|i| point(&sim.unwrapped_position(i)))
        .collect()
}

fn point(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Unwrapped positions of chosen particles, one frame per observation (the first frame is taken
/// when the observer is made).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MemberFrames {
    pub every: u64,
    /// Particle indices recorded, in this order in every frame.
    pub members: Vec<usize>,
    /// Step of each frame.
    pub steps: Vec<u64>,
    pub frames: Vec<Vec<[f64; 3]>>,
}

impl MemberFrames {
    /// Records `members` of `sim` now, then every `every` steps.
    pub fn new(sim: &Simulation, members: Vec<usize>, every: u64) -> Result<Self> {
        if let Some(&i) = members.iter().find(|&&i| i >= sim.particles.len()) {
            return Err(DemError::InvalidConfig(format!(
                "member {i} of a frame recorder is not one of the {} particles",
                sim.particles.len()
            )));
        }
        let first = members
            .iter()
            .map(|&i| point(&sim.particles.pos[i]))
            .collect();
        Ok(MemberFrames {
            every,
            members,
            steps: vec![sim.step_count()],
            frames: vec![first],
        })
    }
}

impl Observer for MemberFrames {
    fn every(&self) -> u64 {
        self.every
    }
    fn observe(&mut self, sim: &Simulation) -> Result<()> {
        let mut cur: Vec<[f64; 3]> = self
            .members
            .iter()
            .map(|&i| point(&sim.particles.pos[i]))
            .collect();
        if let Some(prev) = self.frames.last() {
            unwrap_frame(prev, &mut cur, &periodicity(&sim.sim_box))
                .map_err(|e| DemError::InvalidConfig(e.to_string()))?;
        }
        self.steps.push(sim.step_count());
        self.frames.push(cur);
        Ok(())
    }
}

/// One sample of [`GroupForce`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ForceSample {
    pub step: u64,
    pub time: f64,
    /// Pair force of everything else on the group.
    pub force: [f64; 3],
    /// Displacement of the group since the observer was made (unwrapped).
    pub displacement: [f64; 3],
}

/// The pair force on a group of particles (a wall) and its displacement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroupForce {
    pub every: u64,
    pub members: Vec<usize>,
    /// Unwrapped position of the first member at the last sample (displacements follow it).
    reference: [f64; 3],
    origin: [f64; 3],
    pub samples: Vec<ForceSample>,
}

impl GroupForce {
    /// Records the force on `members` (at least one) every `every` steps.
    pub fn new(sim: &Simulation, members: Vec<usize>, every: u64) -> Result<Self> {
        let Some(&first) = members.first() else {
            return Err(DemError::InvalidConfig(
                "a force recorder needs at least one member".into(),
            ));
        };
        if let Some(&i) = members.iter().find(|&&i| i >= sim.particles.len()) {
            return Err(DemError::InvalidConfig(format!(
                "member {i} of a force recorder is not one of the {} particles",
                sim.particles.len()
            )));
        }
        let x = point(&sim.particles.pos[first]);
        Ok(GroupForce {
            every,
            members,
            reference: x,
            origin: x,
            samples: Vec::new(),
        })
    }
}

impl Observer for GroupForce {
    fn every(&self) -> u64 {
        self.every
    }
    fn observe(&mut self, sim: &Simulation) -> Result<()> {
        let f = sim.forces();
        let total = self.members.iter().fold(Vec3::zeros(), |a, &i| a + f[i]);
        let mut x = [point(&sim.particles.pos[self.members[0]])];
        unwrap_frame(&[self.reference], &mut x, &periodicity(&sim.sim_box))
            .map_err(|e| DemError::InvalidConfig(e.to_string()))?;
        self.reference = x[0];
        self.samples.push(ForceSample {
            step: sim.step_count(),
            time: sim.time(),
            force: point(&total),
            displacement: std::array::from_fn(|a| x[0][a] - self.origin[a]),
        });
        Ok(())
    }
}

/// Dump frames (LAMMPS text format) appended to one file, with integer label columns. The bytes
/// written so far are part of its state: a resumed run first cuts the file back to them, so frames
/// written after the last saved progress are not doubled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Dump {
    pub every: u64,
    pub path: PathBuf,
    /// Column name and one value per particle.
    pub labels: Vec<(String, Vec<u32>)>,
    /// Length of the file after the last frame this observer wrote.
    pub bytes: u64,
}

impl Dump {
    /// A new dump at `path` (an existing file is replaced), first frame written now.
    pub fn new(
        sim: &Simulation,
        path: PathBuf,
        labels: Vec<(String, Vec<u32>)>,
        every: u64,
    ) -> Result<Self> {
        crate::io::progress::remove(&path)?;
        let mut d = Dump {
            every,
            path,
            labels,
            bytes: 0,
        };
        d.observe(sim)?;
        Ok(d)
    }

    /// Cuts the file back to the frames this observer recorded (after a resume).
    pub fn truncate_to_recorded(&self) -> Result<()> {
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(&self.path)
            .map_err(|e| DemError::io(&self.path, e))?;
        f.set_len(self.bytes)
            .map_err(|e| DemError::io(&self.path, e))
    }
}

impl Observer for Dump {
    fn every(&self) -> u64 {
        self.every
    }
    fn observe(&mut self, sim: &Simulation) -> Result<()> {
        let labels: Vec<(&str, &[u32])> = self
            .labels
            .iter()
            .map(|(n, v)| (n.as_str(), v.as_slice()))
            .collect();
        append_labeled_frame(sim, &self.path, &labels)?;
        self.bytes = std::fs::metadata(&self.path)
            .map_err(|e| DemError::io(&self.path, e))?
            .len();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::hcp::hcp_lattice;
    use crate::{Material, PairModel, Parallelism, RunConfig};

    /// Records the steps it sees and whether the virials of that step were computed.
    struct Seen {
        every: u64,
        virial: bool,
        steps: Vec<(u64, bool)>,
    }

    impl Observer for Seen {
        fn every(&self) -> u64 {
            self.every
        }
        fn wants_virial(&self) -> bool {
            self.virial
        }
        fn observe(&mut self, sim: &Simulation) -> Result<()> {
            let has = sim.virial_step() == Some(sim.step_count());
            self.steps.push((sim.step_count(), has));
            Ok(())
        }
    }

    fn sim(par: Parallelism) -> Simulation {
        let (mut p, bx) = hcp_lattice(6, 6, 4, 90.0, 1.0, [true; 3]).unwrap();
        for (i, v) in p.vel.iter_mut().enumerate() {
            *v = Vec3::new(0.01 * (i % 7) as f64, -0.02 * (i % 3) as f64, 0.0);
        }
        let model = PairModel::cohesive(Material::table4(0.15));
        Simulation::new(p, bx, model, vec![], RunConfig::default(), par).unwrap()
    }

    #[test]
    fn observers_see_their_steps_and_the_trajectory_is_that_of_single_steps() {
        let mut a = sim(Parallelism::Threads(2));
        let mut three = Seen {
            every: 3,
            virial: true,
            steps: vec![],
        };
        let mut five = Seen {
            every: 5,
            virial: false,
            steps: vec![],
        };
        a.step().unwrap();
        a.run_observed(16, &mut [&mut three, &mut five]).unwrap();
        let steps = |s: &Seen| s.steps.iter().map(|x| x.0).collect::<Vec<_>>();
        assert_eq!(steps(&three), [3, 6, 9, 12, 15]);
        assert_eq!(steps(&five), [5, 10, 15]);
        assert!(
            three.steps.iter().all(|x| x.1),
            "virials computed for the observer that wants them"
        );
        let mut b = sim(Parallelism::Sequential);
        for _ in 0..17 {
            b.step().unwrap();
        }
        let bits = |s: &Simulation| -> Vec<u64> {
            let p = &s.particles;
            (0..p.len())
                .flat_map(|i| {
                    (0..3).flat_map(move |k| [p.pos[i][k].to_bits(), p.vel[i][k].to_bits()])
                })
                .collect()
        };
        assert_eq!(a.step_count(), 17);
        assert_eq!(bits(&a), bits(&b));
    }
}
