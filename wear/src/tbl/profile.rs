//! Height profiles of a sliding system (paper 004 Fig. 4): the height between the bottom of the system
//! and the top of the top body, H, is cut into `n` bins of equal height; the horizontal velocity of a
//! bin is the mean of the velocities of the particles whose centres lie in it, and its density the mass
//! it holds per unit volume.
//!
//! Decision (density of thin bins): paper 004 bins the height into 400 sectors, four per particle
//! diameter at L = 100 d0. Counting whole particles by their centres would make such thin bins swing
//! between zero and several particles; each particle instead puts into every bin the share of its mass
//! that the bin's slab cuts out of its sphere (exact: the volume of a spherical segment), so the profile
//! is a mass density whose integral over the height is the mass of the system, and a homogeneous solid
//! reads as a flat profile at its bulk density.
//!
//! The agitation of a bin (the granular temperature's square root, in units of v0) is
//! sqrt((<|v|^2> - <v_x>^2) / 3) / v0 over the particles whose centres fall in it, all samples
//! together. Decision (mean flow): the mean velocity is taken along x only, the sliding direction; the
//! mean v_y and v_z of a bin vanish in steady sliding (constant height, periodic z), and what the bin's
//! mean v_x does from sample to sample counts as agitation, as it is motion the mean flow does not
//! carry. Measured because the sheared layer's shear stress falls as it heats (docs/sliding.md).

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};

/// Volume of the part of a sphere (centre height `yc`, radius `r`) between the heights `a < b`:
/// pi (r^2 t - t^3 / 3) between the two cuts, t measured from the centre.
pub fn sphere_slab_volume(yc: f64, r: f64, a: f64, b: f64) -> f64 {
    let lo = (a - yc).max(-r);
    let hi = (b - yc).min(r);
    if hi <= lo {
        return 0.0;
    }
    std::f64::consts::PI * (r * r * (hi - lo) - (hi * hi * hi - lo * lo * lo) / 3.0)
}

/// `n` bins of equal height over [lo, lo + height).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bins {
    pub lo: f64,
    pub height: f64,
    pub n: usize,
}

impl Bins {
    /// Bins over [lo, lo + height); refuses a non-positive height or no bin.
    pub fn new(lo: f64, height: f64, n: usize) -> Result<Self> {
        if !(lo.is_finite() && height.is_finite() && height > 0.0) || n == 0 {
            return Err(WearError::Setting(format!(
                "profile bins need a finite start, a positive height and at least one bin (lo {lo}, \
                 height {height}, {n} bins)"
            )));
        }
        Ok(Bins { lo, height, n })
    }

    /// Height of one bin.
    pub fn width(&self) -> f64 {
        self.height / self.n as f64
    }

    /// The bin holding height `y`, if inside.
    pub fn index(&self, y: f64) -> Option<usize> {
        let k = ((y - self.lo) / self.width()).floor();
        (k >= 0.0 && k < self.n as f64).then_some(k as usize)
    }

    /// Centre of bin `k` over the height: (k + 1/2) / n.
    pub fn centre_over_height(&self, k: usize) -> f64 {
        (k as f64 + 0.5) / self.n as f64
    }
}

/// One sample's particles, one entry each: centre heights, radii, masses, horizontal velocities and
/// squared speeds |v|^2.
#[derive(Debug, Clone, Copy)]
pub struct ProfileParticles<'a> {
    pub y: &'a [f64],
    pub radius: &'a [f64],
    pub mass: &'a [f64],
    pub vx: &'a [f64],
    pub speed_sq: &'a [f64],
}

/// Sums of a profile over samples taken at possibly different heights H (each sample bins its own
/// height): per bin, the sum of horizontal velocities, of squared speeds and the particle count, and
/// the sum of the mass densities of the samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProfileSums {
    pub velocity: Vec<f64>,
    /// Sum of |v|^2 per bin; empty when unknown (sums saved before it was recorded, or merged with
    /// such sums): the profile then has no agitation.
    #[serde(default)]
    pub speed_sq: Vec<f64>,
    pub count: Vec<u64>,
    pub density: Vec<f64>,
    /// Samples added.
    pub samples: u64,
    /// Sum of the heights H and of the reference velocities v0 of the samples.
    pub height: f64,
    pub v0: f64,
}

impl ProfileSums {
    /// Empty sums over `n` bins.
    pub fn new(n: usize) -> Self {
        ProfileSums {
            velocity: vec![0.0; n],
            speed_sq: vec![0.0; n],
            count: vec![0; n],
            density: vec![0.0; n],
            samples: 0,
            height: 0.0,
            v0: 0.0,
        }
    }

    /// Back to empty (keeps the buffers).
    pub fn clear(&mut self) {
        self.velocity.iter_mut().for_each(|v| *v = 0.0);
        // Empty sums know their squares again (an old checkpoint's window is over).
        self.speed_sq.resize(self.count.len(), 0.0);
        self.speed_sq.iter_mut().for_each(|v| *v = 0.0);
        self.count.iter_mut().for_each(|v| *v = 0);
        self.density.iter_mut().for_each(|v| *v = 0.0);
        self.samples = 0;
        self.height = 0.0;
        self.v0 = 0.0;
    }

    /// Adds one sample of particles binned over `bins`; `area` is the cross-section normal to the
    /// height (bin volume = area x width), `v0` the reference velocity of the sample (the top body's).
    /// Particles outside the bins add nothing.
    pub fn add(
        &mut self,
        bins: &Bins,
        particles: ProfileParticles,
        area: f64,
        v0: f64,
    ) -> Result<()> {
        let ProfileParticles {
            y,
            radius: r,
            mass: m,
            vx,
            speed_sq: v2,
        } = particles;
        let n = y.len();
        if r.len() != n
            || m.len() != n
            || vx.len() != n
            || v2.len() != n
            || self.count.len() != bins.n
        {
            return Err(WearError::Setting(format!(
                "a profile sample needs one height, radius, mass, velocity and squared speed per \
                 particle and the sums' bin count ({} bins, {} heights, {} radii, {} masses, {} \
                 velocities, {} squared speeds)",
                bins.n,
                n,
                r.len(),
                m.len(),
                vx.len(),
                v2.len()
            )));
        }
        if !(area.is_finite() && area > 0.0) {
            return Err(WearError::Setting(format!(
                "profile cross-section {area} must be positive"
            )));
        }
        if self.samples == 0 {
            self.speed_sq.resize(bins.n, 0.0);
        }
        let squares = self.speed_sq.len() == bins.n;
        let w = bins.width();
        let bin_volume = area * w;
        for i in 0..n {
            if let Some(k) = bins.index(y[i]) {
                self.velocity[k] += vx[i];
                if squares {
                    self.speed_sq[k] += v2[i];
                }
                self.count[k] += 1;
            }
            let sphere = 4.0 / 3.0 * std::f64::consts::PI * r[i] * r[i] * r[i];
            let per_volume = m[i] / sphere / bin_volume;
            // The bins the sphere reaches, clipped to the profile.
            let first = ((y[i] - r[i] - bins.lo) / w).floor();
            let last = ((y[i] + r[i] - bins.lo) / w).floor();
            if last < 0.0 || first >= bins.n as f64 {
                continue;
            }
            let (first, last) = (first.max(0.0) as usize, (last as usize).min(bins.n - 1));
            for k in first..=last {
                let a = bins.lo + k as f64 * w;
                self.density[k] += per_volume * sphere_slab_volume(y[i], r[i], a, a + w);
            }
        }
        self.samples += 1;
        self.height += bins.height;
        self.v0 += v0;
        Ok(())
    }

    /// Adds the samples of `other` (same bin count) to these.
    pub fn merge(&mut self, other: &ProfileSums) -> Result<()> {
        if other.count.len() != self.count.len() {
            return Err(WearError::Setting(format!(
                "profiles of {} and {} bins cannot be merged",
                self.count.len(),
                other.count.len()
            )));
        }
        let n = self.count.len();
        // The squares stay known only if both sides know theirs (empty sums have none to lose).
        let known = |s: &ProfileSums| s.samples == 0 || s.speed_sq.len() == n;
        if known(self) && known(other) {
            self.speed_sq.resize(n, 0.0);
            for (a, b) in self.speed_sq.iter_mut().zip(&other.speed_sq) {
                *a += b;
            }
        } else {
            self.speed_sq.clear();
        }
        for k in 0..n {
            self.velocity[k] += other.velocity[k];
            self.count[k] += other.count[k];
            self.density[k] += other.density[k];
        }
        self.samples += other.samples;
        self.height += other.height;
        self.v0 += other.v0;
        Ok(())
    }

    /// The averaged profile: mean velocity and agitation over the mean v0 per bin (`None` where no
    /// particle centre fell, or the squares are unknown), and mean density per bin.
    pub fn profile(&self) -> Profile {
        let s = self.samples.max(1) as f64;
        let v0 = self.v0 / s;
        let squares = self.speed_sq.len() == self.count.len();
        Profile {
            agitation_over_v0: (0..self.count.len())
                .map(|k| {
                    let c = self.count[k] as f64;
                    (squares && c > 0.0).then(|| {
                        let (mean, mean_sq) = (self.velocity[k] / c, self.speed_sq[k] / c);
                        // Round-off can leave a tiny negative variance in a bin moving as one.
                        ((mean_sq - mean * mean).max(0.0) / 3.0).sqrt() / v0
                    })
                })
                .collect(),
            velocity_over_v0: self
                .velocity
                .iter()
                .zip(&self.count)
                .map(|(&v, &c)| (c > 0).then(|| v / c as f64 / v0))
                .collect(),
            density: self.density.iter().map(|d| d / s).collect(),
            height: self.height / s,
            v0,
        }
    }
}

/// An averaged profile over the normalised height y / H (bin k at (k + 1/2) / n).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Profile {
    /// Mean horizontal velocity over v0 per bin (`None`: no particle centre in the bin).
    pub velocity_over_v0: Vec<Option<f64>>,
    /// Agitation over v0 per bin, sqrt((<|v|^2> - <v_x>^2) / 3) / v0 (module docs; `None`: no
    /// particle centre in the bin, or unknown).
    #[serde(default)]
    pub agitation_over_v0: Vec<Option<f64>>,
    /// Mass density per bin.
    pub density: Vec<f64>,
    /// Mean height H and reference velocity v0 of the samples.
    pub height: f64,
    pub v0: f64,
}

impl Profile {
    /// Bin centres over H.
    pub fn centres(&self) -> Vec<f64> {
        let n = self.density.len();
        (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parts<'a>(
        y: &'a [f64],
        radius: &'a [f64],
        mass: &'a [f64],
        vx: &'a [f64],
        speed_sq: &'a [f64],
    ) -> ProfileParticles<'a> {
        ProfileParticles {
            y,
            radius,
            mass,
            vx,
            speed_sq,
        }
    }

    #[test]
    fn slabs_cut_the_sphere_exactly() {
        let r = 0.7;
        let full = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        assert!((sphere_slab_volume(1.0, r, -5.0, 5.0) - full).abs() < 1e-14);
        // A hemisphere, and a cap of height h: pi h^2 (3r - h) / 3.
        assert!((sphere_slab_volume(1.0, r, 1.0, 9.0) - full / 2.0).abs() < 1e-14);
        let h = 0.2;
        let cap = std::f64::consts::PI * h * h * (3.0 * r - h) / 3.0;
        assert!((sphere_slab_volume(1.0, r, 1.0 + r - h, 3.0) - cap).abs() < 1e-14);
        assert_eq!(sphere_slab_volume(1.0, r, 2.0, 3.0), 0.0);
        // Slices add up to the sphere.
        let sum: f64 = (0..40)
            .map(|k| sphere_slab_volume(1.0, r, 0.0 + 0.05 * k as f64, 0.05 * (k + 1) as f64))
            .sum();
        assert!((sum - full).abs() < 1e-13);
    }

    #[test]
    fn binning_conserves_mass_and_reads_velocities_per_bin() {
        // Three particles in a 1 x 1 cross-section, height 4 in 8 bins.
        let bins = Bins::new(0.0, 4.0, 8).unwrap();
        let y = [0.6, 2.2, 3.4];
        let r = [0.3, 0.5, 0.25];
        let m = [1.0, 2.0, 0.5];
        let vx = [0.0, 0.4, 1.0];
        let mut s = ProfileSums::new(8);
        s.add(&bins, parts(&y, &r, &m, &vx, &vx.map(|v| v * v)), 1.0, 1.0)
            .unwrap();
        let mut other = ProfileSums::new(8);
        other
            .add(&bins, parts(&y, &r, &m, &vx, &vx.map(|v| v * v)), 1.0, 1.0)
            .unwrap();
        s.merge(&other).unwrap();
        assert!(s.merge(&ProfileSums::new(3)).is_err());
        assert_eq!(s.samples, 2);
        let p = s.profile();
        let mass: f64 = p.density.iter().map(|d| d * bins.width()).sum();
        assert!((mass - 3.5).abs() < 1e-13, "{mass}");
        assert_eq!(p.velocity_over_v0[1], Some(0.0));
        assert_eq!(p.velocity_over_v0[4], Some(0.4));
        assert_eq!(p.velocity_over_v0[6], Some(1.0));
        assert_eq!(p.velocity_over_v0[0], None);
        // The particle at 2.2 (r = 0.5) reaches bins 3 (1.5..2) to 5 (2.5..3) only.
        let share = |k: usize| p.density[k] * bins.width();
        let cut = |a: f64, b: f64| {
            2.0 * sphere_slab_volume(2.2, 0.5, a, b) / (4.0 / 3.0 * std::f64::consts::PI * 0.125)
        };
        assert!((share(4) - cut(2.0, 2.5)).abs() < 1e-14);
        assert_eq!(p.centres()[0], 1.0 / 16.0);
        // Particles partly outside the bins put in only what is inside.
        let mut edge = ProfileSums::new(8);
        edge.add(
            &bins,
            parts(&[0.1], &[0.3], &[1.0], &[0.0], &[0.0]),
            1.0,
            1.0,
        )
        .unwrap();
        let inside: f64 = edge.density.iter().map(|d| d * bins.width()).sum();
        let expect =
            sphere_slab_volume(0.1, 0.3, 0.0, 1.0) / (4.0 / 3.0 * std::f64::consts::PI * 0.027);
        assert!((inside - expect).abs() < 1e-14);
    }

    #[test]
    fn a_homogeneous_lattice_reads_flat_at_its_bulk_density() {
        // Spheres on a simple cubic lattice of spacing 1 (radius 0.5, mass 1): bulk density 1.
        let (mut y, mut r, mut m, mut v) = (vec![], vec![], vec![], vec![]);
        for i in 0..10 {
            for j in 0..20 {
                for k in 0..10 {
                    let _ = (i, k);
                    y.push(j as f64 + 0.5);
                    r.push(0.5);
                    m.push(1.0);
                    v.push(j as f64 / 19.0);
                }
            }
        }
        let bins = Bins::new(0.0, 20.0, 80).unwrap();
        let mut s = ProfileSums::new(80);
        let v2: Vec<f64> = v.iter().map(|v| v * v).collect();
        s.add(&bins, parts(&y, &r, &m, &v, &v2), 100.0, 1.0)
            .unwrap();
        let p = s.profile();
        // Each unit layer holds one sphere's mass per unit area; thin bins see the sphere's shape, so
        // the mean over a layer is exactly 1.
        for layer in p.density.chunks(4) {
            let mean: f64 = layer.iter().sum::<f64>() / 4.0;
            assert!((mean - 1.0).abs() < 1e-12, "{mean}");
        }
    }

    #[test]
    fn bad_samples_are_refused() {
        assert!(Bins::new(0.0, 0.0, 4).is_err());
        assert!(Bins::new(0.0, 1.0, 0).is_err());
        let bins = Bins::new(0.0, 1.0, 4).unwrap();
        let mut s = ProfileSums::new(4);
        assert!(s
            .add(
                &bins,
                parts(&[0.5], &[0.1, 0.2], &[1.0], &[0.0], &[0.0]),
                1.0,
                1.0
            )
            .is_err());
        assert!(s
            .add(
                &bins,
                parts(&[0.5], &[0.1], &[1.0], &[0.0], &[0.0]),
                0.0,
                1.0
            )
            .is_err());
        assert!(ProfileSums::new(3)
            .add(
                &bins,
                parts(&[0.5], &[0.1], &[1.0], &[0.0], &[0.0]),
                1.0,
                1.0
            )
            .is_err());
        assert!(s
            .add(&bins, parts(&[0.5], &[0.1], &[1.0], &[0.0], &[]), 1.0, 1.0)
            .is_err());
    }

    #[test]
    fn agitation_is_the_velocity_spread_about_the_bins_mean_flow() {
        // One bin; two samples of two particles each. Velocities (vx, vy, vz): sample 1 (1, 0, 0) and
        // (3, 0, 0), sample 2 (2, 1, 0) and (2, -1, 0): mean vx 2 over the four, <|v|^2> = (1 + 9 + 5
        // + 5) / 4 = 5, so the agitation is sqrt((5 - 4) / 3) / v0 with v0 = 2.
        let bins = Bins::new(0.0, 1.0, 1).unwrap();
        let mut s = ProfileSums::new(1);
        let (y, r, m) = ([0.5, 0.5], [0.1, 0.1], [1.0, 1.0]);
        s.add(&bins, parts(&y, &r, &m, &[1.0, 3.0], &[1.0, 9.0]), 1.0, 2.0)
            .unwrap();
        s.add(&bins, parts(&y, &r, &m, &[2.0, 2.0], &[5.0, 5.0]), 1.0, 2.0)
            .unwrap();
        let p = s.profile();
        assert_eq!(p.velocity_over_v0[0], Some(1.0));
        let expect = (1.0f64 / 3.0).sqrt() / 2.0;
        assert!((p.agitation_over_v0[0].unwrap() - expect).abs() < 1e-15);
        // A bin moving as one has none (the square root of a round-off negative is not taken).
        let mut rigid = ProfileSums::new(1);
        rigid
            .add(
                &bins,
                parts(&y, &r, &m, &[0.1, 0.1], &[0.01, 0.01]),
                1.0,
                2.0,
            )
            .unwrap();
        assert_eq!(rigid.profile().agitation_over_v0[0], Some(0.0));
        // Sums saved before the squares were recorded know no agitation, also once merged, until
        // they are cleared for the next window.
        let mut old = s.clone();
        old.speed_sq.clear();
        assert_eq!(old.profile().agitation_over_v0[0], None);
        let mut merged = s.clone();
        merged.merge(&old).unwrap();
        assert_eq!(merged.profile().agitation_over_v0[0], None);
        old.add(&bins, parts(&y, &r, &m, &[1.0, 3.0], &[1.0, 9.0]), 1.0, 2.0)
            .unwrap();
        assert_eq!(old.profile().agitation_over_v0[0], None);
        old.clear();
        old.add(&bins, parts(&y, &r, &m, &[1.0, 3.0], &[1.0, 9.0]), 1.0, 2.0)
            .unwrap();
        assert!(old.profile().agitation_over_v0[0].is_some());
        // Empty sums merged with full ones take their squares.
        let mut empty = ProfileSums::new(1);
        empty.merge(&s).unwrap();
        assert_eq!(empty.profile(), p);
    }
}
