//! Force laws (paper 000 Figs. 2-3, A.1-A.3): the engine's own functions (`dem::force::normal_force`,
//! `tangential_cap`, `PairModel::params`) against the paper's formulas, written again here from the
//! text (eqs 3, 5, 7-11, 15-16, 20, A.33, A.49), so that a slip in either shows as a difference.
//! Pure function evaluations: nothing to cache.

use dem::force::{normal_force, tangential_cap};
use dem::{Material, PairModel, PairParams};

use crate::report::{Claim, Context, Figure, Kind, Panel, Section, SectionOutput, Tolerance};
use crate::Result;

pub const SECTION: Section = Section {
    id: "force-laws",
    title: "Force laws (paper 000 section 2, Figs. 2-3, A.1-A.3)",
    run,
};

/// The seven pair parameters from the paper's formulas (eqs 7-11, 15-16, A.49), with the elastic
/// limit min(delta_e, delta_f) of the engine's documented reading of eq (10) above d_c (Fig. A.2: the
/// force ends at delta_f').
#[derive(Debug, Clone, Copy)]
struct Closed {
    k_n: f64,
    k_t: f64,
    /// eq (9), before the min with delta_f.
    delta_e: f64,
    delta_f: f64,
    f_mt: f64,
    a_n: f64,
}

fn closed(m: &Material, ri: f64, rj: f64) -> Closed {
    let (e, nu, sn) = (m.young_modulus, m.poisson_ratio, m.tensile_strength);
    let reff = ri.min(rj);
    let a_n = 2f64.sqrt() * reff * reff / (1.0 - 2.0 * nu);
    let a_t = 2f64.sqrt() * reff * reff * (1.0 - 4.0 * nu) / ((1.0 - 2.0 * nu) * (1.0 + nu));
    let d = ri + rj;
    let d_c = 4.0 * m.surface_energy * e / (sn * sn);
    let delta_e = d * sn / e;
    let delta_f = if d <= d_c {
        4.0 * m.surface_energy / sn
    } else {
        delta_e * (d / d_c).powf(-m.scaling)
    };
    Closed {
        k_n: a_n * e / d,
        k_t: a_t * e / d,
        delta_e,
        delta_f,
        f_mt: a_t * m.shear_strength,
        a_n,
    }
}

/// Eq (3) with the elastic limit min(delta_e, delta_f).
fn eq3(c: &Closed, dn: f64) -> f64 {
    let de = c.delta_e.min(c.delta_f);
    if dn <= de {
        c.k_n * dn
    } else if dn <= c.delta_f {
        -c.k_n * de / (c.delta_f - de) * (dn - c.delta_f)
    } else {
        0.0
    }
}

/// Eq (3) with the uncorrected delta_f = 4 gamma / sigma_N above d_c (Fig. A.1: the force drops to
/// zero at delta_f before reaching the elastic limit).
fn eq3_uncorrected(c: &Closed, m: &Material, dn: f64) -> f64 {
    let df = 4.0 * m.surface_energy / m.tensile_strength;
    if dn <= df {
        c.k_n * dn
    } else {
        0.0
    }
}

/// Eq (5).
fn eq5(c: &Closed, dn: f64) -> f64 {
    ((c.delta_f - dn) / c.delta_f).clamp(0.0, 1.0) * c.f_mt
}

fn grid(lo: f64, hi: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |k| lo + (hi - lo) * k as f64 / n as f64)
}

fn params(m: &Material, ri: f64, rj: f64) -> PairParams {
    let (mi, mj) = (1.0, 1.0);
    PairModel::cohesive(m.clone()).params(ri, rj, mi, mj)
}

/// Points (x, y) of one curve.
type Curve = Vec<(f64, f64)>;

/// The engine's normal force and eq 3's at `delta_N / delta_e` = each x, both over k_N delta_e.
fn normal_curves(p: &PairParams, c: &Closed, xs: impl Iterator<Item = f64>) -> (Curve, Curve) {
    let scale = c.k_n * c.delta_e;
    xs.map(|x| {
        let dn = x * c.delta_e;
        ((x, normal_force(p, dn) / scale), (x, eq3(c, dn) / scale))
    })
    .unzip()
}

fn run(_ctx: &Context) -> Result<SectionOutput> {
    let base = Material::table4(0.15);
    let d_c = base.critical_diameter();
    let fig = "force-laws";
    let mut claims = Vec::new();

    // Fig. 2: below d_c.
    let r = 0.3 * d_c;
    let (p, c) = (params(&base, r, r), closed(&base, r, r));
    let (engine, formula) = normal_curves(&p, &c, grid(-1.0, 1.15 * c.delta_f / c.delta_e, 400));
    claims.push(max_gap_claim(
        "Fig. 2, eq 3",
        "normal force F_N(delta_N), d = 0.6 d_c: max |engine - eq 3| / (k_N delta_e)",
        &engine,
        &formula,
    ));
    let fig2 = Panel::new(
        "normal force: engine vs eq 3 (Fig. 2)",
        "delta_N / delta_e (-)",
        "F_N / (k_N delta_e) (-), cohesive > 0",
    )
    .with("r_i + r_j = 0.6 d_c", Kind::Simulation, engine)
    .with("r_i + r_j = 0.6 d_c", Kind::Reference, formula);

    // Eq (5), the cap of Fig. 3.
    let xs: Vec<f64> = grid(-0.3, 1.1, 280).collect();
    let engine: Vec<(f64, f64)> = xs
        .iter()
        .map(|&x| (x, tangential_cap(&p, x * c.delta_f) / c.f_mt))
        .collect();
    let formula: Vec<(f64, f64)> = xs
        .iter()
        .map(|&x| (x, eq5(&c, x * c.delta_f) / c.f_mt))
        .collect();
    claims.push(max_gap_claim(
        "Fig. 3, eq 5",
        "tangential cap F'_mT(delta_N): max |engine - eq 5| / F_mT",
        &engine,
        &formula,
    ));
    let fig3 = Panel::new(
        "tangential force cap: engine vs eq 5 (Fig. 3)",
        "delta_N / delta_f (-)",
        "F'_mT / F_mT (-)",
    )
    .with("F'_mT, r_i + r_j = 0.6 d_c", Kind::Simulation, engine)
    .with("F'_mT, r_i + r_j = 0.6 d_c", Kind::Reference, formula);

    // Figs. A.1-A.2: above d_c, s = 0 and 1/2 against the corrected delta_f'; A.1 uncorrected.
    let r = d_c; // r_i + r_j = 2 d_c
    let mut a12 = Panel::new(
        "r_i + r_j = 2 d_c: engine vs eqs 3, A.49 (Figs. A.1-A.2)",
        "delta_N / delta_e (eq 9) (-)",
        "F_N / (k_N delta_e) (-)",
    );
    for s in [0.0, 0.5] {
        let m = Material {
            scaling: s,
            ..base.clone()
        };
        let (p, c) = (params(&m, r, r), closed(&m, r, r));
        let xs: Vec<f64> = grid(-0.5, 1.3, 360).collect();
        let (engine, formula) = normal_curves(&p, &c, xs.iter().copied());
        claims.push(max_gap_claim(
            "Fig. A.2, eqs 3, A.49",
            &format!(
                "normal force at 2 d_c, s = {s}: max |engine - eq 3 with delta_f'| / (k_N delta_e)"
            ),
            &engine,
            &formula,
        ));
        a12 = a12.with(format!("s = {s}"), Kind::Simulation, engine).with(
            format!("s = {s}"),
            Kind::Reference,
            formula,
        );
        if s == 0.0 {
            let scale = c.k_n * c.delta_e;
            let un: Vec<(f64, f64)> = xs
                .iter()
                .map(|&x| (x, eq3_uncorrected(&c, &m, x * c.delta_e) / scale))
                .collect();
            a12 = a12.with("delta_f = 4 gamma/sigma_N (A.1)", Kind::Reference, un);
        }
    }

    // Fig. A.3 and eq (20): the matched strength E delta_e' / d and the matched surface energy
    // U / (2 A_N) (A.31-A.33) from the engine's parameters, against eq 20 and (d / d_c)^(1 - 2s).
    let sizes: Vec<f64> = (0..=24)
        .map(|k| 10f64.powf(-0.7 + 2.0 * k as f64 / 24.0))
        .collect();
    let mut a3 = Panel::new(
        "matched strength: engine vs eq 20 (Fig. A.3)",
        "(r_i + r_j) / d_c (-)",
        "sigma'_N / sigma_N (-)",
    )
    .log_x();
    let mut gam = Panel::new(
        "bond energy: engine vs (d/d_c)^(1-2s) (A.31-A.33)",
        "(r_i + r_j) / d_c (-)",
        "U_gamma / (2 A_N gamma) (-)",
    )
    .log_x();
    for s in [0.0, 0.5, 1.0] {
        let m = Material {
            scaling: s,
            ..base.clone()
        };
        let (mut strength, mut energy, mut ref_s, mut ref_g) = (vec![], vec![], vec![], vec![]);
        for &x in &sizes {
            let r = 0.5 * x * d_c;
            let p = params(&m, r, r);
            let a_n = p.k_n * 2.0 * r / m.young_modulus; // eq 7 read backwards
            let peak = normal_force(&p, p.delta_e);
            strength.push((x, peak / a_n / m.tensile_strength));
            energy.push((x, p.bond_energy() / (2.0 * a_n) / m.surface_energy));
            ref_s.push((x, if x <= 1.0 { 1.0 } else { x.powf(-s) }));
            ref_g.push((x, if x <= 1.0 { 1.0 } else { x.powf(1.0 - 2.0 * s) }));
        }
        let at = sizes[18]; // 10^0.8 = 6.3 d_c
        let label = format!("s = {s}");
        if s == 0.5 {
            let got = strength[18].1;
            claims.push(
                Claim::new(
                    "000",
                    "Fig. A.3, eq 20",
                    format!("sigma'_N / sigma_N at d = {:.2} d_c, s = 1/2", at),
                    at.powf(-0.5),
                    got,
                    Tolerance::Relative(1e-9),
                )
                .plotted(fig, &a3.title, &label, at),
            );
            claims.push(
                Claim::new(
                    "000",
                    "eq A.33",
                    format!("U_gamma / (2 A_N gamma) at d = {:.2} d_c, s = 1/2", at),
                    1.0,
                    energy[18].1,
                    Tolerance::Relative(1e-9),
                )
                .plotted(fig, &gam.title, &label, at),
            );
        }
        a3 = a3
            .with(label.clone(), Kind::SimulationPoints, strength)
            .with(label.clone(), Kind::Reference, ref_s);
        gam = gam
            .with(label.clone(), Kind::SimulationPoints, energy)
            .with(label, Kind::Reference, ref_g);
    }

    // Eqs 7-11 for an unequal pair, each parameter against the closed form.
    let (ri, rj) = (0.2 * d_c, 0.3 * d_c);
    let (p, c) = (params(&base, ri, rj), closed(&base, ri, rj));
    let worst = [
        (p.k_n, c.k_n),
        (p.k_t, c.k_t),
        (p.delta_e, c.delta_e.min(c.delta_f)),
        (p.delta_f, c.delta_f),
        (p.f_mt, c.f_mt),
    ]
    .iter()
    .map(|(a, b)| ((a - b) / b).abs())
    .fold(0.0, f64::max);
    claims.push(Claim::new(
        "000",
        "eqs 7-11, 14-16",
        "pair parameters of r = (0.2, 0.3) d_c: max relative |engine - formula|",
        0.0,
        worst,
        Tolerance::Absolute(1e-12),
    ));
    let _ = c.a_n;

    let figure = Figure {
        columns: 2,
        ..Figure::new(fig, "paper 000 Figs. 2, 3, A.1, A.2, A.3", "The pair force of the engine against the paper's formulas (Table 4 material, nu = 0.15).")
    }
    .panel(fig2)
    .panel(fig3)
    .panel(a12)
    .panel(a3)
    .panel(gam);
    Ok(SectionOutput {
        claims,
        figures: vec![figure],
        html: "<p>Each curve is the engine's own function evaluated on a grid; the dashed curves are the \
               paper's formulas, coded again in <code>validation/src/report/sections/force_laws.rs</code>. \
               Above d_c the engine ends the force at delta_f' (the module docs of <code>dem::material</code>: \
               eq 3 read literally would keep the Hookean branch past delta_f'), which is what Fig. A.2 and eq 20 describe.</p>\n"
            .into(),
        provenance: vec![],
    })
}

/// Largest |a - b| over two curves on the same grid, as a claim against 0.
fn max_gap_claim(item: &str, quantity: &str, a: &[(f64, f64)], b: &[(f64, f64)]) -> Claim {
    let gap = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p.1 - q.1).abs())
        .fold(0.0, f64::max);
    Claim::new("000", item, quantity, 0.0, gap, Tolerance::Absolute(1e-12))
}
