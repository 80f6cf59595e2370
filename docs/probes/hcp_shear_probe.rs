//! Probe of 4 Dec (docs/patch-tests.md, "HCP lattice"): the HCP shear and tensile peaks at nu = 0
//! with the lattice in four orientations, and the shear peak with the top wall under a small
//! pressure instead of at fixed height. TURN 0: close-packed layers in the x-y plane (stacked along
//! z, normal to the walls' plane), rows along the shear (x), as shipped; 1: the same layers turned by
//! 90 degrees in their plane (rows along y); 2: layers in the x-z plane (stacked along y, parallel to
//! the walls: the shear slides them over each other), rows along x; 3: as 2 with rows along z. Not built by the workspace; to run it:
//!   cp docs/probes/hcp_shear_probe.rs dem/examples/ && cargo build --release -p dem --example hcp_shear_probe
//!   target/release/examples/hcp_shear_probe D0_OVER_DC TURN PRESSURE [S]
//! (TURN 0-3; PRESSURE in E, 0 for the fixed-height test only), e.g. `0.6 0 0`, `2.4 1 0`,
//! `0.6 0 1e-4`, `9.6 0 0 0.5`. S is the scaling exponent of eq 10 (default 0). Prints the peaks over
//! the target strengths of eq 20.
use dem::material::{Material, PairModel};
use dem::sample::Sample;
use dem::scenario::patch::compaction::{compaction, CompactionConfig};
use dem::scenario::patch::strength::{strength, StrengthConfig, StrengthMode};
use dem::{Parallelism, SimBox, Vec3};

fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|v| v.parse().unwrap())
        .collect();
    let (d0_over_dc, turn, pressure) = (a[0], a[1] as u32, a[2]);
    let mut m = Material::table4(0.0);
    m.scaling = a.get(3).copied().unwrap_or(0.0);
    let model = PairModel::cohesive(m.clone());
    let d = d0_over_dc * m.critical_diameter();
    let dims = if turn == 3 {
        Vec3::new(3.0 * d, 8.0 * d, 8.0 * d)
    } else if turn == 2 {
        Vec3::new(8.0 * d, 3.0 * d, 8.0 * d)
    } else {
        Vec3::new(8.0 * d, 8.0 * d, 3.0 * d)
    };
    let mut s = Sample::hcp(dims, d, 1.0).unwrap();
    if turn == 1 || turn == 3 {
        swap_axes(&mut s, 0, 1);
    }
    if turn >= 2 {
        swap_axes(&mut s, 1, 2);
    }
    let mut cfg = StrengthConfig::paper(StrengthMode::Shear);
    cfg.post_peak_strain = 0.02;
    let fixed = strength(&s, &model, &cfg, Parallelism::Threads(1)).unwrap();
    println!(
        "d0/dc {d0_over_dc} turned {turn}: fixed height peak / target {:.4}",
        fixed.ratio
    );
    let mut tc = StrengthConfig::paper(StrengthMode::Tensile);
    tc.post_peak_strain = 0.02;
    let t = strength(&s, &model, &tc, Parallelism::Threads(1)).unwrap();
    println!("  tensile peak / target {:.4}", t.ratio);
    if pressure > 0.0 {
        let c = CompactionConfig {
            pressure,
            strain: 0.3,
            max_compaction: 1.0,
            ..CompactionConfig::default()
        };
        let r = compaction(&s, &model, &c, Parallelism::Threads(1)).unwrap();
        let peak = r
            .curve
            .points
            .iter()
            .map(|q| q.stress[3].abs())
            .fold(0.0, f64::max);
        let wall = r
            .curve
            .points
            .iter()
            .map(|q| q.wall_traction_x.abs())
            .fold(0.0, f64::max);
        println!(
            "  under {pressure} E: peak sigma_xy / target {:.4} (wall traction {:.4})",
            peak / m.shear_strength,
            wall / m.shear_strength
        );
    }
}

/// Exchanges axes `a` and `b` of the sample's positions and box (the lattice is turned with them).
fn swap_axes(s: &mut Sample, a: usize, b: usize) {
    let swap = |v: Vec3| {
        let mut w = v;
        w[a] = v[b];
        w[b] = v[a];
        w
    };
    for p in s.particles.pos.iter_mut() {
        *p = swap(*p);
    }
    s.sim_box = SimBox::new(swap(s.sim_box.lo), swap(s.sim_box.hi), [true; 3]).unwrap();
}
