//! Outcome of a sheared junction: plastic smoothing, or a wear particle that detached and rolls.
//! One decision for MD and DEM: inputs are plain positions (unwrapped, one `Vec` per frame, the same
//! junction members in the same order; [`unwrap_frame`] makes them so), bonds and force histories;
//! nothing here knows LAMMPS or the DEM engine.
//!
//! The decision (paper 000 section 4; Aghababaei et al. 2016): a wear particle has *detached* and
//! *rolls*, i.e. the junction material turns as a body. Between successive frames we fit a rigid
//! in-plane motion to the junction members ([`rotation::plane_fit`]); summing gives the total turn and
//! the non-rigid residual. Homogeneous shear turns a material's shape by at most pi/2 (the polar
//! rotation atan(gamma / 2)), whatever its amount, and with a residual as large as the turn
//! (`rigidity` near 1). A junction with at least `min_members` members is a wear particle when either
//! - it rolls as a rigid body: `|turn| >= min_turn` and `rigidity <= max_rigidity` (the rule the MD
//!   model junctions were classified with), or
//! - it came off as one body and turned beyond what shear can turn: the cluster analysis of
//!   [`detachment`] puts at least `min_debris_fraction` of the members in one body that lost every
//!   original bond chain to the walls, and `|turn| > pi/2`.
//!
//! Why the second rule (measured, docs/junction.md): coarse DEM debris (d0 = 6 nm, tens of particles)
//! deforms while it rolls under the normal load, so its frame-to-frame fit leaves a residual above the
//! rigid rule's 0.5 although the junction has visibly come off and flipped over (D = 32 nm, seed 2:
//! debris 0.90 of the members, turn 1.9 rad, rigidity 1.5). The MD junctions' verdicts are the same
//! under both rules (D = 12 sigma: turn 0.54, debris 0.08; D = 50 sigma: turn 2.6, rigidity 0.18).
//!
//! Also reported, not part of the decision: the tangential force history (peak, and the late mean over
//! the peak: it drops once the junction has come off).

pub mod cluster;
pub mod rotation;

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};
pub use cluster::{
    detachment, loose_clusters, Bonding, Detachment, LooseCluster, LooseClusters, Periodicity,
};

/// Verdict classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    PlasticSmoothing,
    WearParticle,
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Outcome::PlasticSmoothing => "plastic smoothing",
            Outcome::WearParticle => "wear particle",
        })
    }
}

/// Thresholds of the decision.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClassifyParams {
    /// rad; above pi/2, the most a junction's shape can turn under any amount of homogeneous
    /// shear (polar rotation atan(gamma/2)), so only a body that rolls gets past it.
    pub min_turn: f64,
    /// Non-rigid / rigid displacement ratio; 0.5 sits between rolling (~0) and shear flow (~1).
    pub max_rigidity: f64,
    /// In-plane axes (shear direction, normal direction); rotation is about the third axis.
    pub axes: (usize, usize),
    /// Fewest members that can make a wear particle; default 4: a particle or two coming loose is
    /// debris of no size, and their rigid fit is degenerate (one point has no rotation).
    pub min_members: usize,
    /// Fraction of the members in one detached body for the second rule; default 0.5: most of the
    /// junction came off together.
    pub min_debris_fraction: f64,
}

impl Default for ClassifyParams {
    fn default() -> Self {
        Self {
            min_turn: 2.0,
            max_rigidity: 0.5,
            axes: (0, 1),
            min_members: 4,
            min_debris_fraction: 0.5,
        }
    }
}

impl ClassifyParams {
    fn validate(&self) -> Result<()> {
        let ok = self.min_turn.is_finite()
            && self.min_turn > 0.0
            && self.max_rigidity.is_finite()
            && self.max_rigidity > 0.0
            && self.axes.0 < 3
            && self.axes.1 < 3
            && self.axes.0 != self.axes.1
            && (0.0..=1.0).contains(&self.min_debris_fraction);
        if ok {
            Ok(())
        } else {
            Err(WearError::Setting(format!(
                "classifier thresholds {self:?}: min_turn and max_rigidity must be positive, the two \
                 axes distinct and below 3, min_debris_fraction in [0, 1]"
            )))
        }
    }
}

/// The decision with its evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    pub outcome: Outcome,
    /// Which rule decided, in words.
    pub reason: String,
    /// Signed total turn of the junction (rad), sum of frame-to-frame rigid rotations.
    pub turn: f64,
    /// Sum of non-rigid RMS residuals / sum of rotational RMS displacements (|dtheta| x radius).
    pub rigidity: f64,
    /// Cumulative turn after each frame (first frame 0).
    pub turn_history: Vec<f64>,
    /// Peak |tangential force| and the mean over the last quarter divided by it (None if no force).
    pub force_peak: Option<f64>,
    pub force_late_over_peak: Option<f64>,
    /// Cluster analysis of the first and last frames (None when the caller had no bonds to give).
    #[serde(default)]
    pub detachment: Option<Detachment>,
}

/// Checks that `frames` describe one set of members over time: at least two frames, all of the same
/// length, finite coordinates.
fn check_frames(frames: &[Vec<[f64; 3]>]) -> Result<()> {
    if frames.len() < 2 {
        return Err(WearError::Frames(format!(
            "{} frame(s): a turn needs at least two",
            frames.len()
        )));
    }
    let n = frames[0].len();
    if let Some(k) = frames.iter().position(|f| f.len() != n) {
        return Err(WearError::Frames(format!(
            "frame {k} has {} members, frame 0 has {n}: every frame must list the same members in the \
             same order",
            frames[k].len()
        )));
    }
    for (k, f) in frames.iter().enumerate() {
        if let Some(i) = f.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
            return Err(WearError::Frames(format!(
                "frame {k}, member {i}: non-finite coordinate {:?}",
                f[i]
            )));
        }
    }
    Ok(())
}

/// Classifies from junction member positions per frame, (optionally, empty otherwise) the tangential
/// force sampled at the same frames, and (optionally) the cluster analysis of [`detachment`].
pub fn classify(
    frames: &[Vec<[f64; 3]>],
    tangential_force: &[f64],
    detachment: Option<Detachment>,
    p: &ClassifyParams,
) -> Result<Verdict> {
    p.validate()?;
    check_frames(frames)?;
    if !tangential_force.is_empty() && tangential_force.len() != frames.len() {
        return Err(WearError::Frames(format!(
            "{} force samples for {} frames: give one per frame, or none",
            tangential_force.len(),
            frames.len()
        )));
    }
    if let Some(k) = tangential_force.iter().position(|f| !f.is_finite()) {
        return Err(WearError::Frames(format!(
            "force sample {k} is {}",
            tangential_force[k]
        )));
    }
    let mut turn = 0.0;
    let (mut res_sum, mut rot_sum) = (0.0, 0.0);
    let mut turn_history = vec![0.0];
    for w in frames.windows(2) {
        let f = rotation::plane_fit(&w[0], &w[1], p.axes);
        turn += f.angle;
        res_sum += f.residual;
        rot_sum += f.angle.abs() * f.radius;
        turn_history.push(turn);
    }
    let rigidity = if rot_sum > 0.0 {
        res_sum / rot_sum
    } else {
        f64::INFINITY
    };
    let members = frames[0].len();
    let debris = detachment.as_ref().map(|d| d.debris_fraction);
    let (outcome, reason) = if members < p.min_members {
        (
            Outcome::PlasticSmoothing,
            format!(
                "{members} member(s): fewer than the {} a wear particle needs",
                p.min_members
            ),
        )
    } else if turn.abs() >= p.min_turn && rigidity <= p.max_rigidity {
        (
            Outcome::WearParticle,
            format!(
                "rolls as a rigid body: turned {:.2} rad (>= {}) with rigidity {rigidity:.2} (<= {})",
                turn.abs(),
                p.min_turn,
                p.max_rigidity
            ),
        )
    } else if debris.is_some_and(|f| f >= p.min_debris_fraction)
        && turn.abs() > std::f64::consts::FRAC_PI_2
    {
        (
            Outcome::WearParticle,
            format!(
                "came off as one body ({:.0} % of the members, >= {:.0} %) and turned {:.2} rad, beyond \
                 the pi/2 that shear can turn material",
                100.0 * debris.unwrap_or(0.0),
                100.0 * p.min_debris_fraction,
                turn.abs()
            ),
        )
    } else {
        (
            Outcome::PlasticSmoothing,
            format!(
                "turned {:.2} rad with rigidity {rigidity:.2}{}: neither a rigid roll nor a detached body \
                 turned beyond pi/2",
                turn.abs(),
                debris.map_or(String::new(), |f| format!(", {:.0} % of the members in a loose body", 100.0 * f))
            ),
        )
    };
    let (force_peak, force_late_over_peak) = force_features(tangential_force);
    Ok(Verdict {
        outcome,
        reason,
        turn,
        rigidity,
        turn_history,
        force_peak,
        force_late_over_peak,
        detachment,
    })
}

fn force_features(f: &[f64]) -> (Option<f64>, Option<f64>) {
    if f.is_empty() {
        return (None, None);
    }
    let peak = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let late = &f[f.len() - (f.len() / 4).max(1)..];
    let mean = late.iter().map(|v| v.abs()).sum::<f64>() / late.len() as f64;
    (
        Some(peak),
        if peak > 0.0 { Some(mean / peak) } else { None },
    )
}

/// Makes `cur` continuous with `prev` across periodic boundaries: each coordinate on a periodic axis
/// is shifted by whole periods to lie within half a period of the same member's previous position.
/// Frames must be taken often enough that no member moves half a period between two of them.
pub fn unwrap_frame(prev: &[[f64; 3]], cur: &mut [[f64; 3]], per: &Periodicity) -> Result<()> {
    if prev.len() != cur.len() {
        return Err(WearError::Frames(format!(
            "cannot unwrap a frame of {} members against one of {}",
            cur.len(),
            prev.len()
        )));
    }
    for (c, p) in cur.iter_mut().zip(prev) {
        for (k, period) in per.0.iter().enumerate() {
            if let Some(l) = period {
                c[k] -= l * ((c[k] - p[k]) / l).round();
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
