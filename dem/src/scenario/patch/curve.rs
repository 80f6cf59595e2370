//! Stress-strain curves of the patch tests, written as CSV.

use std::io::Write;
use std::path::Path;

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use crate::error::{DemError, Result};

/// One recorded state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CurvePoint {
    pub step: u64,
    /// Shear strain (top-wall displacement along x over L0).
    pub strain_xy: f64,
    /// Normal strain (change of wall separation over L0).
    pub strain_yy: f64,
    /// Virial stress of the deformable part, tension positive: xx, yy, zz, xy, xz, yz.
    pub stress: [f64; 6],
    /// Pair force on the top wall per unit area (y, x).
    pub wall_traction_y: f64,
    pub wall_traction_x: f64,
}

impl CurvePoint {
    /// Packs a stress tensor into the six components stored.
    pub fn components(s: &Matrix3<f64>) -> [f64; 6] {
        [
            s[(0, 0)],
            s[(1, 1)],
            s[(2, 2)],
            s[(0, 1)],
            s[(0, 2)],
            s[(1, 2)],
        ]
    }
}

/// A recorded stress-strain curve.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    pub points: Vec<CurvePoint>,
}

impl Curve {
    /// Writes the curve as CSV with a header line.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| DemError::io(dir, e))?;
        }
        let file = std::fs::File::create(path).map_err(|e| DemError::io(path, e))?;
        let mut w = std::io::BufWriter::new(file);
        let io = |e| DemError::io(path, e);
        writeln!(
            w,
            "step,strain_xy,strain_yy,sxx,syy,szz,sxy,sxz,syz,wall_traction_y,wall_traction_x"
        )
        .map_err(io)?;
        for p in &self.points {
            let s = p.stress;
            writeln!(
                w,
                "{},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}",
                p.step,
                p.strain_xy,
                p.strain_yy,
                s[0],
                s[1],
                s[2],
                s[3],
                s[4],
                s[5],
                p.wall_traction_y,
                p.wall_traction_x
            )
            .map_err(io)?;
        }
        w.flush().map_err(io)
    }
}
