//! The cell grid of the neighbour search, and the particles binned into it: a uniform grid over the
//! box (periodic axes) or over the particles' extent (open axes), each cell's particles by ascending
//! radius so that a search for one particle's partners can stop at the first partner larger (or, from
//! the other end, smaller) than the particle.

use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::Vec3;

use super::{positive_image, Image, PairRange};

/// Particles binned into a [`CellGrid`], each cell's run by ascending radius (ties by index), with
/// positions and radii copied in cell order so that a cell's candidates are read from one run of
/// memory.
pub(super) struct Binned {
    grid: CellGrid,
    cell_start: Vec<u32>,
    cell_particles: Vec<u32>,
    cell_xr: Vec<[f64; 4]>,
    /// Reach of the largest particle: every pair's cutoff plus skin is below it.
    reach_max: f64,
    /// `beyond_contact` of the largest particle: the screen for a partner of any size.
    beyond_max: f64,
}

/// Scratch of one searching thread: each axis's stencil offsets (see [`CellGrid::for_each_cell_within`]).
pub(super) type Steps = [Vec<AxisStep>; 3];

impl Binned {
    /// Bins `pos` (wrapped into the box) with the cell edge of [`cell_edge`].
    pub(super) fn new(
        pos: &[Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
        skin: f64,
    ) -> Result<Self> {
        let r_max = radius.iter().cloned().fold(0.0, f64::max);
        let reach_max = range.max_cutoff(r_max) + skin;
        let grid = CellGrid::new(pos, bx, reach_max, cell_edge(radius, range, skin))?;
        let (cell_start, mut cell_particles) = grid.bin(pos);
        // Each cell's particles by ascending radius (ties by index), so that a particle's scan of a
        // cell stops at the first larger partner: those pairs are found from the other side.
        for w in cell_start.windows(2) {
            cell_particles[w[0] as usize..w[1] as usize].sort_unstable_by(|&a, &b| {
                radius[a as usize]
                    .total_cmp(&radius[b as usize])
                    .then(a.cmp(&b))
            });
        }
        let cell_xr = cell_particles
            .iter()
            .map(|&j| {
                let (x, r) = (pos[j as usize], radius[j as usize]);
                [x.x, x.y, x.z, r]
            })
            .collect();
        Ok(Binned {
            grid,
            cell_start,
            cell_particles,
            cell_xr,
            reach_max,
            beyond_max: range.beyond_contact(r_max),
        })
    }

    /// Calls `f(j, image)` for every partner `j` within cutoff plus skin that particle `i` is larger
    /// than (r_j < r_i, or equal radii and j < i), and for `i`'s own images with a positive image:
    /// each pair of a full build is found once, from its larger particle, which searches the cells
    /// within its own reach only (a small particle never scans for the largest partner's range).
    /// The separation and cutoff are evaluated from `i`'s side, as the force loop computes them.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn smaller_partners(
        &self,
        i: usize,
        pos: &[Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
        skin: f64,
        steps: &mut Steps,
        mut f: impl FnMut(usize, Image),
    ) {
        let (xi, ri) = (pos[i], radius[i]);
        // Every partner's cutoff is below this reach; the cheap bound ri + rj + beyond screens
        // candidates before the exact (possibly powf) cutoff is evaluated.
        let reach = range.max_cutoff(ri) + skin;
        let beyond = range.beyond_contact(ri) + skin;
        let grid = &self.grid;
        grid.for_each_cell_within(grid.cell_of(&xi), reach, steps, |cell, img| {
            let o = bx.shift(img) - xi;
            let (s, e) = (
                self.cell_start[cell] as usize,
                self.cell_start[cell + 1] as usize,
            );
            for (&j, &[x, y, z, rj]) in self.cell_particles[s..e].iter().zip(&self.cell_xr[s..e]) {
                // A cell's particles are in ascending radius: the rest are all larger.
                if rj > ri {
                    break;
                }
                let j = j as usize;
                let larger = rj < ri || (rj == ri && j < i);
                if !(larger || (j == i && positive_image(img))) {
                    continue;
                }
                let (dx, dy, dz) = (x + o.x, y + o.y, z + o.z);
                let d2 = dx * dx + dy * dy + dz * dz;
                // (Rounded up by a part in 1e12, so that rounding never lets the screen drop a
                // pair the exact cutoff keeps.)
                let rough = (ri + rj + beyond) * (1.0 + 1e-12);
                if d2 >= rough * rough {
                    continue;
                }
                // The exact test on the separation as the force loop computes it.
                let d2 = (pos[j] + bx.shift(img) - xi).norm_squared();
                let cut = range.cutoff(ri, rj) + skin;
                if d2 < cut * cut {
                    f(j, img);
                }
            }
        });
    }

    /// Calls `f(j, image)` for every partner `j` larger than particle `i` (the pairs
    /// [`Binned::smaller_partners`] finds from `j`'s side), within the largest reach, scanning each
    /// cell from its largest particle down. The exact test is evaluated from `j`'s side, bit for bit
    /// as a full build evaluates it, so a pair is listed or not the same way whichever side found it;
    /// `image` is `j`'s image seen from `i`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn larger_partners(
        &self,
        i: usize,
        pos: &[Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
        skin: f64,
        steps: &mut Steps,
        mut f: impl FnMut(usize, Image),
    ) {
        let (xi, ri) = (pos[i], radius[i]);
        let beyond = self.beyond_max + skin;
        let grid = &self.grid;
        grid.for_each_cell_within(grid.cell_of(&xi), self.reach_max, steps, |cell, img| {
            let o = bx.shift(img) - xi;
            let (s, e) = (
                self.cell_start[cell] as usize,
                self.cell_start[cell + 1] as usize,
            );
            let run = self.cell_particles[s..e].iter().zip(&self.cell_xr[s..e]);
            for (&j, &[x, y, z, rj]) in run.rev() {
                let j = j as usize;
                // From the largest down: the first partner that is not larger ends the cell.
                if !(rj > ri || (rj == ri && j > i)) {
                    break;
                }
                let (dx, dy, dz) = (x + o.x, y + o.y, z + o.z);
                let d2 = dx * dx + dy * dy + dz * dz;
                let rough = (ri + rj + beyond) * (1.0 + 1e-12);
                if d2 >= rough * rough {
                    continue;
                }
                let back = img.map(|s| -s);
                let d2 = (xi + bx.shift(back) - pos[j]).norm_squared();
                let cut = range.cutoff(rj, ri) + skin;
                if d2 < cut * cut {
                    f(j, img);
                }
            }
        });
    }
}

/// The cell edge of a build: the reach of a pair of median particles. Cells sized for the largest
/// range (one cell across it) would hold hundreds of the small particles of a wide size distribution,
/// all of them candidates of every neighbour; with this edge, most particles search their 27 cells
/// and only the larger ones reach further ([`CellGrid::for_each_cell_within`]). Equal spheres get
/// the largest range, as before.
pub(super) fn cell_edge(radius: &[f64], range: &impl PairRange, skin: f64) -> f64 {
    if radius.is_empty() {
        return 0.0;
    }
    let mut r = radius.to_vec();
    let mid = r.len() / 2;
    let (_, median, _) = r.select_nth_unstable_by(mid, f64::total_cmp);
    range.max_cutoff(*median) + skin
}

/// Uniform cell grid over the box (periodic axes) or over the particles' extent (other axes).
pub(super) struct CellGrid {
    lo: Vec3,
    size: Vec3,
    n: [usize; 3],
    periodic: [bool; 3],
}

impl CellGrid {
    /// A grid of cells of about `edge` (at least one per axis, at most about 8 per particle), over a
    /// box whose periodic axes must be longer than the largest reach `rc`.
    pub(super) fn new(pos: &[Vec3], bx: &SimBox, rc: f64, edge: f64) -> Result<Self> {
        let mut lo = bx.lo;
        let mut ext = bx.lengths();
        let mut n = [1usize; 3];
        // Cap the grid at about 8 cells per particle so sparse non-periodic systems stay cheap.
        let cap = ((8 * pos.len().max(1)) as f64).cbrt().ceil() as usize + 2;
        for a in 0..3 {
            if bx.periodic[a] {
                if ext[a] < rc {
                    return Err(DemError::InvalidBox(format!(
                        "periodic axis {a} is {:.6e} long, shorter than one interaction range plus skin ({rc:.6e})",
                        ext[a]
                    )));
                }
            } else {
                let (mn, mx) = pos
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), x| {
                        (mn.min(x[a]), mx.max(x[a]))
                    });
                if pos.is_empty() {
                    lo[a] = 0.0;
                    ext[a] = rc;
                } else {
                    lo[a] = mn;
                    ext[a] = (mx - mn).max(rc) * (1.0 + 1e-9);
                }
            }
            n[a] = ((ext[a] / edge.max(1e-300 * ext[a])).floor() as usize).clamp(1, cap);
        }
        let size = Vec3::new(
            ext[0] / n[0] as f64,
            ext[1] / n[1] as f64,
            ext[2] / n[2] as f64,
        );
        Ok(CellGrid {
            lo,
            size,
            n,
            periodic: bx.periodic,
        })
    }

    fn count(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    fn coords(&self, x: &Vec3) -> [usize; 3] {
        let mut c = [0usize; 3];
        for a in 0..3 {
            let k = ((x[a] - self.lo[a]) / self.size[a]).floor();
            c[a] = (k.max(0.0) as usize).min(self.n[a] - 1);
        }
        c
    }

    fn cell_of(&self, x: &Vec3) -> usize {
        let c = self.coords(x);
        c[0] + self.n[0] * (c[1] + self.n[1] * c[2])
    }

    /// Counting sort of particles into cells: (start offsets, particle indices), stable in index order.
    fn bin(&self, pos: &[Vec3]) -> (Vec<u32>, Vec<u32>) {
        let nc = self.count();
        let cells: Vec<usize> = pos.iter().map(|x| self.cell_of(x)).collect();
        let mut start = vec![0u32; nc + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for k in 0..nc {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut parts = vec![0u32; pos.len()];
        for (p, &c) in cells.iter().enumerate() {
            parts[fill[c] as usize] = p as u32;
            fill[c] += 1;
        }
        (start, parts)
    }

    /// Calls `f(cell, image)` for every cell within `reach` of `cell` (27 cells when the reach is one
    /// cell edge) in the unwrapped tiling, with the image of each periodic copy; every (cell, image)
    /// combination is distinct even when an axis has one or two cells. Images beyond one box length
    /// are left out: positions lie in the box and every range is shorter than it. `steps` is scratch
    /// for the three axes' offsets, reused across calls: a large particle's stencil has hundreds of
    /// cells but only 2k + 1 offsets per axis, each costing an integer division once, not per cell.
    fn for_each_cell_within(
        &self,
        cell: usize,
        reach: f64,
        steps: &mut [Vec<AxisStep>; 3],
        mut f: impl FnMut(usize, Image),
    ) {
        let c = [
            cell % self.n[0],
            (cell / self.n[0]) % self.n[1],
            cell / (self.n[0] * self.n[1]),
        ];
        for (a, out) in steps.iter_mut().enumerate() {
            let k = (reach / self.size[a]).ceil().max(1.0) as i64;
            self.axis_steps(a, c[a], k, out);
        }
        // Cells of a large stencil whose nearest point lies beyond the reach are skipped (about
        // half of the cube for the largest particles); the 27 nearest always stay.
        let reach2 = reach * reach;
        let [xs, ys, zs] = &*steps;
        for sz in zs {
            for sy in ys {
                let gyz = sz.gap2 + sy.gap2;
                if gyz >= reach2 {
                    continue;
                }
                let row = self.n[0] * (sy.cell + self.n[1] * sz.cell);
                for sx in xs {
                    if gyz + sx.gap2 >= reach2 {
                        continue;
                    }
                    f(sx.cell + row, [sx.img, sy.img, sz.img]);
                }
            }
        }
    }

    /// The offsets -k..=k from cell coordinate `c` along axis `a` that exist: the cell, its image
    /// (periodic axes, at most one box length away) and the squared gap between the two cells.
    fn axis_steps(&self, a: usize, c: usize, k: i64, out: &mut Vec<AxisStep>) {
        out.clear();
        let na = self.n[a] as i64;
        for d in -k..=k {
            let u = c as i64 + d;
            let (cell, img) = if self.periodic[a] {
                let img = u.div_euclid(na);
                if img.abs() > 1 {
                    continue;
                }
                (u.rem_euclid(na) as usize, img as i8)
            } else if (0..na).contains(&u) {
                (u as usize, 0)
            } else {
                continue;
            };
            let gap = (d.abs() - 1).max(0) as f64 * self.size[a];
            out.push(AxisStep {
                cell,
                img,
                gap2: gap * gap,
            });
        }
    }
}

/// One offset of a stencil along one axis (see [`CellGrid::axis_steps`]).
pub(super) struct AxisStep {
    cell: usize,
    img: i8,
    gap2: f64,
}
