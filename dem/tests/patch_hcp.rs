//! Patch tests on HCP lattices against paper 000 section 3.1 (Table 4 material, Figs. 5-6, A.4-A.5).
//!
//! Run times (release, this 2-core machine): elastic sweep ~3 s, tensile ~6 s, strength trend ~60 s.
//! The lattice strengths do not depend on L (the deformation is homogeneous up to the peak), so the
//! trend uses L = 8 d0; the elastic sweep uses the paper's L = 25 d0, W = 3 d0.

use dem::sample::Sample;
use dem::scenario::patch::{elastic, strength, ElasticConfig, StrengthConfig, StrengthMode};
use dem::{Material, PairModel, Parallelism, Vec3};

fn hcp(mat: &Material, d0_over_dc: f64, l_over_d0: f64) -> Sample {
    let d0 = d0_over_dc * mat.critical_diameter();
    Sample::hcp(
        Vec3::new(l_over_d0 * d0, l_over_d0 * d0, 3.0 * d0),
        d0,
        mat.density,
    )
    .unwrap()
}

#[test]
fn hcp_young_modulus_and_poisson_ratio_within_12_percent() {
    for nu in [0.0, 0.1, 0.15, 0.2, 0.25] {
        let mat = Material::table4(nu);
        let sample = hcp(&mat, 0.6, 25.0);
        let r = elastic(
            &sample,
            &PairModel::cohesive(mat),
            &ElasticConfig::default(),
            Parallelism::Sequential,
        )
        .unwrap();
        assert!(r.converged, "nu {nu}: {r:?}");
        let e_err = (r.young_modulus - 1.0).abs();
        // Relative error in nu; at nu = 0 the absolute error, on the same 12 % scale of 0.1.
        let nu_err = (r.poisson_ratio - nu).abs() / nu.max(0.1);
        println!(
            "nu {nu}: E {:.4} nu {:.4} ({} steps)",
            r.young_modulus, r.poisson_ratio, r.steps
        );
        assert!(
            e_err < 0.12,
            "nu {nu}: E {} off by more than 12 %",
            r.young_modulus
        );
        assert!(
            nu_err < 0.12,
            "nu {nu}: measured nu {} off by more than 12 %",
            r.poisson_ratio
        );
        // The paper's trend: the error is smallest at nu = 0 and largest at 1/4.
        if nu == 0.0 {
            assert!(e_err < 0.02 && nu_err < 0.02, "{r:?}");
        }
    }
}

#[test]
fn hcp_tensile_strength_within_5_percent_at_nu_0_and_fracture_energy() {
    let mat = Material::table4(0.0);
    let sample = hcp(&mat, 0.6, 10.0);
    let cfg = StrengthConfig::paper(StrengthMode::Tensile);
    let r = strength(
        &sample,
        &PairModel::cohesive(mat),
        &cfg,
        Parallelism::Sequential,
    )
    .unwrap();
    println!(
        "tensile {:.4} (target 0.2) at strain {:.4}, {:?}",
        r.strength, r.strain_at_peak, r.fracture
    );
    assert!(
        (r.ratio.unwrap() - 1.0).abs() < 0.05,
        "tensile strength {} vs 0.2",
        r.strength
    );
    let f = r.fracture.unwrap();
    assert!(f.separated, "{f:?}");
    // Breaking every bond across a plane costs 2 gamma A_N per bond (eqs A.31-A.34): the measured
    // surface energy has the scale of gamma (1.5), larger by the lattice's bond density on that plane.
    assert!(f.surface_energy > 1.5 && f.surface_energy < 3.0, "{f:?}");
    // The wall work also pays the elastic energy released at failure, ~sigma^2 L0 / (2 E) per area.
    assert!(f.work_per_area > 2.0 * f.surface_energy, "{f:?}");
}

/// Peak stress for d0 in {0.6, 2.4, 9.6, 19.2} d_c (Figs. 5-6); returns (strengths, strength / target).
fn strength_vs_d0(s: f64, mode: StrengthMode) -> (Vec<f64>, Vec<f64>) {
    let mut cfg = StrengthConfig::paper(mode);
    // Only the peak is needed here.
    cfg.post_peak_strain = 0.02;
    let (mut values, mut ratios) = (Vec::new(), Vec::new());
    for d0 in [0.6, 2.4, 9.6, 19.2] {
        let mut mat = Material::table4(0.0);
        mat.scaling = s;
        let sample = hcp(&mat, d0, 8.0);
        let r = strength(
            &sample,
            &PairModel::cohesive(mat),
            &cfg,
            Parallelism::Sequential,
        )
        .unwrap();
        println!(
            "s {s} {mode:?} d0 {d0} d_c: {:.4} target {:.4} ratio {:?}",
            r.strength, r.target_strength, r.ratio
        );
        values.push(r.strength);
        ratios.push(
            r.ratio
                .expect("the cohesive law has a target in both modes"),
        );
    }
    (values, ratios)
}

/// Above d_c with s = 0 the model is scale-free (delta_f = delta_e ~ d, k ~ d), so the strengths are flat.
fn assert_flat_above_dc(values: &[f64]) {
    let (lo, hi) = values[1..]
        .iter()
        .fold((f64::INFINITY, 0.0f64), |a, &v| (a.0.min(v), a.1.max(v)));
    assert!(hi / lo < 1.01, "{values:?}");
}

#[test]
fn hcp_tensile_strength_flat_in_d0_for_s_0() {
    let (values, ratios) = strength_vs_d0(0.0, StrengthMode::Tensile);
    assert_flat_above_dc(&values);
    assert!(ratios.iter().all(|r| (r - 1.0).abs() < 0.1), "{ratios:?}");
}

#[test]
fn hcp_tensile_strength_follows_eq20_for_s_half() {
    // Eq (20): the target falls as (d0 / d_c)^(-1/2) above d_c; the measured strengths follow it within 5 %.
    let (_, ratios) = strength_vs_d0(0.5, StrengthMode::Tensile);
    assert!(ratios.iter().all(|r| (r - 1.0).abs() < 0.05), "{ratios:?}");
}

#[test]
fn hcp_shear_strength_flat_in_d0_for_s_0() {
    let (values, ratios) = strength_vs_d0(0.0, StrengthMode::Shear);
    assert_flat_above_dc(&values);
    // Measured: 1.24 below d_c and 1.44 above, where the paper finds the target at nu = 0. The
    // bounds are the lattice's own (docs/patch-tests.md, "Why the lattice is stronger in shear"):
    // eq 11 sizes the tangential caps to carry sigma_T alone, and they do carry 0.89 sigma_T when
    // all sit at F_mT; the normal forces of the inclined bonds add to that, up to the affine peak.
    // Pin the level so that a regression shows.
    assert!(ratios.iter().all(|&r| r > 1.1 && r < 1.6), "{ratios:?}");
    let mat = Material::table4(0.0);
    let dirs = bond_directions(&hcp(&mat, 2.4, 8.0));
    let (caps, affine) = (caps_share(&dirs), affine_first_peak(&dirs, &mat));
    println!("caps alone {caps:.3} sigma_T, affine first peak {affine:.3} sigma_T");
    assert!((caps - 0.894).abs() < 1e-3 && (affine - 1.690).abs() < 1e-2);
    assert!(ratios.iter().all(|&r| r > caps + 0.2), "{ratios:?}");
    assert!(ratios[1..].iter().all(|&r| r < affine), "{ratios:?}");
}

/// Cross section A_N = A_T = sqrt(2) r^2 of eqs 15-16 at nu = 0 and volume per particle d^3 / sqrt(2)
/// of the HCP lattice, for unit diameter.
const AREA: f64 = std::f64::consts::FRAC_1_SQRT_2 / 2.0;
const VOLUME: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The 12 unit bond vectors of a lattice particle: its partners closer than 1.01 d (minimum image).
fn bond_directions(sample: &Sample) -> Vec<Vec3> {
    let p = &sample.particles.pos;
    let (d, size) = (
        2.0 * sample.particles.radius[0],
        sample.sim_box.hi - sample.sim_box.lo,
    );
    let dirs: Vec<Vec3> = p[1..]
        .iter()
        .map(|q| {
            let mut r = q - p[0];
            for a in 0..3 {
                r[a] -= size[a] * (r[a] / size[a]).round();
            }
            r
        })
        .filter(|r| r.norm() < 1.01 * d)
        .map(|r| r.normalize())
        .collect();
    assert_eq!(dirs.len(), 12);
    dirs
}

/// sigma_xy / sigma_T when every tangential spring sits at F_mT = A_T sigma_T (eq 11) along its
/// affine slip and no normal force acts: the share of the shear eq 11 is derived for.
fn caps_share(dirs: &[Vec3]) -> f64 {
    let sxy: f64 = dirs
        .iter()
        .map(|n| {
            let t = slip(n);
            0.25 * AREA * (t.x * n.y + t.y * n.x) / t.norm()
        })
        .sum();
    sxy / VOLUME
}

/// Slip direction of a bond under pure shear eps_xy: the displacement (n_y, n_x, 0) less its normal part.
fn slip(n: &Vec3) -> Vec3 {
    let u = Vec3::new(n.y, n.x, 0.0);
    u - n * u.dot(n)
}

/// First peak of sigma_xy / sigma_T when every bond follows the homogeneous pure shear (spins at the
/// rotation rate: torque-free for k_N = k_T, as at nu = 0), `mat` above d_c with s = 0 (delta_f =
/// delta_e: a bond stretched past delta_e carries nothing, eqs 2-5). Unit diameter; strengths over E.
fn affine_first_peak(dirs: &[Vec3], mat: &Material) -> f64 {
    let (sigma_n, sigma_t) = (
        mat.tensile_strength / mat.young_modulus,
        mat.shear_strength / mat.young_modulus,
    );
    let mut best = 0.0f64;
    for i in 1..10_000 {
        let eps = i as f64 * 1e-4;
        let sxy: f64 = dirs
            .iter()
            .map(|n| {
                let dn = 2.0 * eps * n.x * n.y;
                if dn >= sigma_n {
                    return 0.0;
                }
                let t = slip(n) * eps;
                let cap = AREA * sigma_t * ((sigma_n - dn) / sigma_n).min(1.0);
                let ft = (AREA * t.norm()).min(cap);
                let f = n * (AREA * dn) + t * (ft / t.norm());
                0.25 * (f.x * n.y + f.y * n.x)
            })
            .sum::<f64>()
            / VOLUME;
        if sxy > best {
            best = sxy;
        } else if sxy < 0.9 * best {
            break;
        }
    }
    best / sigma_t
}

#[test]
fn hcp_shear_strength_falls_with_d0_for_s_half() {
    let (values, ratios) = strength_vs_d0(0.5, StrengthMode::Shear);
    // The trend of eq (20): a decrease above d_c, slower than the target's (x0.58 from 2.4 to 19.2 d_c
    // against x0.35), so the ratio grows: the tangential cap F_mT does not scale with s, only the normal
    // bonds do (docs/patch-tests.md). The trend is asserted as the power-law slope over the three sizes
    // above d_c (target -0.5), not point by point: the shear peak of a perfect lattice is reached when
    // slip nucleates from round-off alone, and a mere change of summation order (bit-level, the same
    // physics) moved the 9.6 d_c point between 0.063 and 0.073 while the slope stayed -0.27 to -0.28.
    let (x, y): (Vec<f64>, Vec<f64>) = [2.4f64, 9.6, 19.2]
        .iter()
        .zip(&values[1..])
        .map(|(d, v)| (d.ln(), v.ln()))
        .unzip();
    let (mx, my) = (x.iter().sum::<f64>() / 3.0, y.iter().sum::<f64>() / 3.0);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let slope = sxy / sxx;
    println!("power-law slope above d_c: {slope:.3}");
    assert!(slope < -0.15 && slope > -0.5, "slope {slope}: {values:?}");
    assert!(values[1] < values[0], "{values:?}");
    assert!(values[3] < 0.7 * values[1], "{values:?}");
    assert!(ratios[3] < 3.5, "{ratios:?}");
}

#[test]
fn bad_patch_inputs_are_errors() {
    let mat = Material::table4(0.1);
    let model = PairModel::cohesive(mat.clone());
    let par = Parallelism::Sequential;
    // Too thin for two walls and a free part.
    let thin = hcp(&mat, 0.6, 2.0);
    assert!(elastic(&thin, &model, &ElasticConfig::default(), par).is_err());
    let sample = hcp(&mat, 0.6, 6.0);
    let bad = ElasticConfig {
        stress: -0.01,
        ..ElasticConfig::default()
    };
    assert!(elastic(&sample, &model, &bad, par).is_err());
    let bad = StrengthConfig {
        strain_rate: f64::NAN,
        ..StrengthConfig::paper(StrengthMode::Tensile)
    };
    assert!(strength(&sample, &model, &bad, par).is_err());
    let mut bad_model = model.clone();
    bad_model.scale.k_n = 0.0;
    assert!(strength(
        &sample,
        &bad_model,
        &StrengthConfig::paper(StrengthMode::Shear),
        par
    )
    .is_err());
}
