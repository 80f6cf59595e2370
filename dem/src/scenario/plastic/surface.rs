//! The worn surface of paper 001 (section 2, Fig. 1): N spheres of radius r_s on a hexagonal grid,
//! not interacting with each other, each free to move only vertically. Area per sphere a_s = A / N.
//!
//! Decision (lattice): the grid keeps the paper's a_s = L S / N exactly (it sets the flow force
//! a_s H of every sphere), with a regular hexagonal spacing s from a_s = (sqrt 3 / 2) s^2; the strip
//! then holds round(L / s) x round(S / (s sqrt 3 / 2)) spheres, within a few per cent of L x S (the
//! paper's 9.35 x 1.68 cm with N = 5012 gives 155 x 32 = 4960 spheres on 9.32 x 1.67 cm). Rows run
//! along x; odd rows are shifted by s / 2.
//!
//! Storage is structure of arrays: positions, the tangential history of each sphere's one possible
//! contact (with the projectile) and the vertical displacement of its last step.

use serde::{Deserialize, Serialize};

use crate::error::{not_positive, DemError, Result};

/// The strip as paper 001 section 3 gives it (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SurfaceSpec {
    /// Length L along x (m); default 9.35 cm (paper).
    pub length: f64,
    /// Width S along y (m); default 1.68 cm (paper).
    pub width: f64,
    /// Number of spheres N that sets a_s = L S / N; default 5012 (paper).
    pub spheres: usize,
    /// Sphere radius r_s (m); default 0.25 mm (paper).
    pub sphere_radius: f64,
}

impl Default for SurfaceSpec {
    fn default() -> Self {
        SurfaceSpec {
            length: 0.0935,
            width: 0.0168,
            spheres: 5012,
            sphere_radius: 0.25e-3,
        }
    }
}

impl SurfaceSpec {
    /// Rejects a strip that cannot be built.
    pub fn validate(&self) -> Result<()> {
        if let Some(m) = not_positive(&[
            ("surface.length", self.length),
            ("surface.width", self.width),
            ("surface.sphere_radius", self.sphere_radius),
        ]) {
            return Err(DemError::InvalidConfig(m));
        }
        if self.spheres < 4 {
            return Err(DemError::InvalidConfig(format!(
                "surface.spheres = {} must be at least 4",
                self.spheres
            )));
        }
        let a_s = self.length * self.width / self.spheres as f64;
        let s = (a_s / (0.75f64.sqrt())).sqrt();
        if s < 2.0 * self.sphere_radius * 0.999_999 {
            return Err(DemError::InvalidConfig(format!(
                "surface: {} spheres of radius {} m on {} x {} m overlap (grid spacing {s:.4e} m < 2 r_s)",
                self.spheres, self.sphere_radius, self.length, self.width
            )));
        }
        if self.length < 2.0 * s || self.width < 2.0 * s {
            return Err(DemError::InvalidConfig(
                "surface: the strip must hold at least two rows and two columns".into(),
            ));
        }
        Ok(())
    }
}

/// The spheres of the surface (engine units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Surface {
    /// Spheres per row (along x) and rows (along y).
    pub nx: usize,
    pub ny: usize,
    /// Grid spacing along a row and between rows (s sqrt 3 / 2).
    pub spacing: f64,
    pub row_spacing: f64,
    /// r_s.
    pub radius: f64,
    /// a_s, the area of the flat surface per sphere.
    pub cell_area: f64,
    /// Height of every centre when the surface is flat (eq 6).
    pub z0: f64,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
    /// Tangential history of each sphere's contact with the projectile, one array per component.
    pub xi: [Vec<f64>; 3],
    /// Vertical displacement of each sphere in the last step (negative: down).
    pub dz_last: Vec<f64>,
}

impl Surface {
    /// The hexagonal grid of `spec` in engine units (`to_len` converts metres).
    pub fn hexagonal(spec: &SurfaceSpec, to_len: impl Fn(f64) -> f64) -> Result<Surface> {
        spec.validate()?;
        let (l, w) = (to_len(spec.length), to_len(spec.width));
        let cell_area = l * w / spec.spheres as f64;
        let spacing = (cell_area / 0.75f64.sqrt()).sqrt();
        let row_spacing = spacing * 0.75f64.sqrt();
        let nx = (l / spacing).round().max(2.0) as usize;
        let ny = (w / row_spacing).round().max(2.0) as usize;
        let n = nx * ny;
        let mut x = Vec::with_capacity(n);
        let mut y = Vec::with_capacity(n);
        for j in 0..ny {
            for k in 0..nx {
                x.push((k as f64 + Self::row_offset(j)) * spacing);
                y.push((j as f64 + 0.5) * row_spacing);
            }
        }
        Ok(Surface {
            nx,
            ny,
            spacing,
            row_spacing,
            radius: to_len(spec.sphere_radius),
            cell_area,
            z0: 0.0,
            x,
            y,
            z: vec![0.0; n],
            xi: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            dz_last: vec![0.0; n],
        })
    }

    /// Where sphere k of row j sits along x, in spacings.
    fn row_offset(j: usize) -> f64 {
        0.25 + 0.5 * (j % 2) as f64
    }

    /// Number of spheres.
    pub fn len(&self) -> usize {
        self.z.len()
    }

    /// Whether the surface has no sphere (never, once built).
    pub fn is_empty(&self) -> bool {
        self.z.is_empty()
    }

    /// Length of the strip along x (nx spacings).
    pub fn length(&self) -> f64 {
        self.nx as f64 * self.spacing
    }

    /// Width of the strip along y (ny row spacings).
    pub fn width(&self) -> f64 {
        self.ny as f64 * self.row_spacing
    }

    /// The sphere nearest the point (x, y).
    pub fn nearest_site(&self, x: f64, y: f64) -> usize {
        let j = ((y / self.row_spacing - 0.5).round().max(0.0) as usize).min(self.ny - 1);
        let k =
            ((x / self.spacing - Self::row_offset(j)).round().max(0.0) as usize).min(self.nx - 1);
        j * self.nx + k
    }

    /// Whether the disk of radius `reach` around (x, y) lies inside the strip (with half a spacing
    /// to spare, so that no sphere a contact could need is missing).
    pub fn holds_disk(&self, x: f64, y: f64, reach: f64) -> bool {
        let m = reach + 0.5 * self.spacing;
        x - m >= 0.0 && y - m >= 0.0 && x + m <= self.length() && y + m <= self.width()
    }

    /// Appends to `out`, in increasing index order, every sphere whose centre lies within horizontal
    /// distance `reach` of (x, y) (the candidates for a contact).
    pub fn candidates(&self, x: f64, y: f64, reach: f64, out: &mut Vec<u32>) {
        if reach.is_nan() || reach <= 0.0 {
            return;
        }
        let (dy, s) = (self.row_spacing, self.spacing);
        let j0 = ((y - reach) / dy - 0.5).ceil().max(0.0);
        let j1 = ((y + reach) / dy - 0.5).floor().min(self.ny as f64 - 1.0);
        if j1 < j0 {
            return;
        }
        for j in j0 as usize..=j1 as usize {
            let yj = (j as f64 + 0.5) * dy;
            let half = (reach * reach - (yj - y) * (yj - y)).max(0.0).sqrt();
            let off = Self::row_offset(j);
            let k0 = ((x - half) / s - off).ceil().max(0.0);
            let k1 = ((x + half) / s - off).floor().min(self.nx as f64 - 1.0);
            if k1 < k0 {
                continue;
            }
            let base = j * self.nx;
            out.extend((k0 as usize..=k1 as usize).map(|k| (base + k) as u32));
        }
    }

    /// Wear volume of eq (6): W_V = sum_i (z_0 - z_i) a_s.
    pub fn wear_volume(&self) -> f64 {
        self.z.iter().map(|z| self.z0 - z).sum::<f64>() * self.cell_area
    }

    /// Depth of the deepest sphere below z_0.
    pub fn max_depth(&self) -> f64 {
        self.z.iter().fold(0.0f64, |d, z| d.max(self.z0 - z))
    }

    /// Height of the highest sphere centre (spheres only move down: z_0).
    pub fn top(&self) -> f64 {
        self.z0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> Surface {
        // In mm, as the engine sees it.
        Surface::hexagonal(&SurfaceSpec::default(), |m| m * 1e3).unwrap()
    }

    #[test]
    fn paper_strip_keeps_its_area_per_sphere() {
        let s = paper();
        // a_s = L S / N = 93.5 * 16.8 / 5012 mm^2 ~ 0.31 mm^2 (paper 001 section 3).
        assert!((s.cell_area - 93.5 * 16.8 / 5012.0).abs() < 1e-12);
        assert!((s.cell_area - 0.3134).abs() < 1e-3);
        assert_eq!((s.nx, s.ny, s.len()), (155, 32, 4960));
        assert!((s.length() - 93.5).abs() / 93.5 < 0.01 && (s.width() - 16.8).abs() / 16.8 < 0.01);
        // Hexagonal cells tile the strip: N a_s = strip area.
        assert!((s.len() as f64 * s.cell_area - s.length() * s.width()).abs() < 1e-9);
        // Spheres do not overlap (non-interacting, but the grid must be a surface of spheres).
        assert!(s.spacing > 2.0 * s.radius);
        assert_eq!(s.wear_volume(), 0.0);
    }

    #[test]
    fn candidates_are_exactly_the_spheres_within_reach() {
        let s = paper();
        let mut got = Vec::new();
        for &(x, y, reach) in &[
            (40.0, 8.0, 2.3),
            (40.13, 8.41, 0.6),
            (0.2, 0.1, 1.5),
            (93.0, 16.5, 3.0),
            (50.0, 8.0, 0.01),
        ] {
            got.clear();
            s.candidates(x, y, reach, &mut got);
            let brute: Vec<u32> = (0..s.len())
                .filter(|&i| (s.x[i] - x).hypot(s.y[i] - y) <= reach)
                .map(|i| i as u32)
                .collect();
            assert_eq!(got, brute, "disk ({x}, {y}, {reach})");
        }
        got.clear();
        s.candidates(40.0, 8.0, 0.0, &mut got);
        assert!(got.is_empty());
    }

    #[test]
    fn nearest_site_and_edges() {
        let s = paper();
        let i = s.nearest_site(46.7, 8.4);
        let d = (s.x[i] - 46.7).hypot(s.y[i] - 8.4);
        assert!((0..s.len()).all(|k| (s.x[k] - 46.7).hypot(s.y[k] - 8.4) >= d - 1e-12));
        assert!(s.holds_disk(46.7, 8.4, 3.0));
        assert!(!s.holds_disk(46.7, 8.4, 8.5));
        assert!(!s.holds_disk(1.0, 8.4, 1.0));
    }

    #[test]
    fn bad_strips_are_errors() {
        let spec = SurfaceSpec {
            sphere_radius: 0.5e-3,
            ..SurfaceSpec::default()
        };
        assert!(spec.validate().is_err(), "overlapping spheres");
        let spec = SurfaceSpec {
            width: -1.0,
            ..SurfaceSpec::default()
        };
        assert!(spec.validate().is_err());
        let spec = SurfaceSpec {
            spheres: 2,
            ..SurfaceSpec::default()
        };
        assert!(spec.validate().is_err());
    }
}
