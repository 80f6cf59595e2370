//! Outcome of a sheared junction: plastic smoothing, or a wear particle that detached and rolls.
//! Shared by MD and DEM: inputs are plain positions (unwrapped, one `Vec` per frame, the same
//! junction members in the same order), bonds and force histories; nothing here knows LAMMPS.
//!
//! The decision (paper 000 section 4; Aghababaei et al. 2016): a wear particle *rolls*, i.e. the
//! junction material turns as a body. Between successive frames we fit a rigid in-plane motion to
//! the junction members ([`rotation::plane_fit`]); summing gives the total turn and the non-rigid
//! residual. Plastic flow also turns material (vorticity), but with a residual as large as the
//! turn (`rigidity` near 1 for simple shear); a rolling particle turns with a small residual.
//! So: wear particle iff `|turn| >= min_turn` and `rigidity <= max_rigidity`. The tangential force
//! history and the detached fraction from the cluster analysis are reported as corroborating
//! evidence (force drops after detachment; the debris' cluster loses both walls).

pub mod cluster;
pub mod rotation;

use serde::{Deserialize, Serialize};

/// Verdict classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    PlasticSmoothing,
    WearParticle,
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
}

impl Default for ClassifyParams {
    fn default() -> Self {
        Self {
            min_turn: 2.0,
            max_rigidity: 0.5,
            axes: (0, 1),
        }
    }
}

/// The decision with its evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    pub outcome: Outcome,
    /// Signed total turn of the junction (rad), sum of frame-to-frame rigid rotations.
    pub turn: f64,
    /// Sum of non-rigid RMS residuals / sum of rotational RMS displacements (|dtheta| x radius).
    pub rigidity: f64,
    /// Cumulative turn after each frame (first frame 0).
    pub turn_history: Vec<f64>,
    /// Peak |tangential force| and the mean over the last quarter divided by it (None if no force).
    pub force_peak: Option<f64>,
    pub force_late_over_peak: Option<f64>,
}

/// Classifies from junction member positions per frame and (optionally) the tangential force.
pub fn classify(frames: &[Vec<[f64; 3]>], tangential_force: &[f64], p: &ClassifyParams) -> Verdict {
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
    let outcome = if turn.abs() >= p.min_turn && rigidity <= p.max_rigidity {
        Outcome::WearParticle
    } else {
        Outcome::PlasticSmoothing
    };
    let (force_peak, force_late_over_peak) = force_features(tangential_force);
    Verdict {
        outcome,
        turn,
        rigidity,
        turn_history,
        force_peak,
        force_late_over_peak,
    }
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

#[cfg(test)]
mod tests;
