//! The section's figure (Fig. 6's two panels and the resolution study's) and its page: the
//! set-up, the strength tests' table, the runs' table and one run's pictures.

use super::super::super::html::esc;
use super::resolution::resolution_panel;
use super::{l_over_d0, on_grid, RunOut, StrengthOut};
use crate::report::{Figure, Kind, Panel, Profile};
use crate::wear::sliding::{SlidingSummary, StrengthJob};

pub(super) fn figure(runs: &[&SlidingSummary], grid_d0: f64) -> Figure {
    // Fig. 6's panels hold the grid's runs only (the resolution study's finer box has its own).
    let grid: Vec<&SlidingSummary> = runs
        .iter()
        .filter(|r| on_grid(r, grid_d0))
        .copied()
        .collect();
    let series = |sigma_m: f64| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = grid
            .iter()
            .filter(|r| r.strength == sigma_m)
            .map(|r| (r.p_n, r.rho_tbl))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let mut by_pressure = Panel::new(
        "rho_TBL against p_N (Fig. 6a)",
        "normal pressure p_N (E)",
        "rho_TBL / rho_0 (-)",
    );
    for s in [0.1, 0.14, 0.2] {
        let pts = series(s);
        if pts.len() > 1 {
            by_pressure = by_pressure.with(format!("sigma_m = {s} E"), Kind::SimulationPoints, pts);
        }
    }
    by_pressure = by_pressure.with(
        "rho_0 (the relaxed solid)",
        Kind::Reference,
        vec![(0.01, 1.0), (0.04, 1.0)],
    );
    let mut by_strength: Vec<(f64, f64)> = grid
        .iter()
        .filter(|r| r.p_n == 0.01)
        .map(|r| (r.strength, r.rho_tbl))
        .collect();
    by_strength.sort_by(|a, b| a.0.total_cmp(&b.0));
    let fig_b = Panel::new(
        "rho_TBL against sigma_m at fixed d* (Fig. 6b)",
        "strength sigma_m (E)",
        "rho_TBL / rho_0 (-)",
    )
    .with("p_N = 0.01 E", Kind::SimulationPoints, by_strength)
    .with(
        "rho_0 (the relaxed solid)",
        Kind::Reference,
        vec![(0.1, 1.0), (0.2, 1.0)],
    );
    let fig = Figure::new(
        "sliding-rho",
        "paper 004 Fig. 6",
        "Density of the third-body layer against the normal pressure and the strength; the paper's trends: rising with p_N, higher for a stronger material.",
    )
    .panel(by_pressure)
    .panel(fig_b);
    match resolution_panel(runs, grid_d0) {
        None => fig,
        Some(panel) => fig.panel(panel),
    }
}

pub(super) fn page(
    outs: &[RunOut],
    strengths: &[StrengthOut],
    jobs: &[StrengthJob],
    profile: Profile,
) -> String {
    let mut h = String::from(
        "<p>Quasi-2D box L x L x 3 d0 of paper 004 with the normal-only force (nu = 1/4), log-normal \
         sizes, two halves with a non-matching interface, the top body under p_N dragged at \
         0.1 sqrt(E/rho), brought there from rest at 0.5 tau_m / (rho L) (a velocity step would send \
         2.4 tau_m into the sigma_m = 0.1 E sample and break it at the body's face; \
         docs/sliding.md); E = rho = L = 1. \
         rho_TBL is the minimum of the Gaussian fitted to the Savitzky-Golay filtered density \
         profile, averaged over the steady half of the run. A TBL whose boundary lies within half a \
         diameter of a rigid body's face has reached the body (the phase paper 004 drops, label \
         boundary_reached); the interior phase is the windows after the first tenth of the run whose \
         TBL lies inside the material, the paper's first stationary phase. Wear particles are the \
         clusters of layer material of at least 10 particles whose bonds of one window ago persist \
         and reach neither body (the junction's cluster rule; Fig. 3a and 3c); the largest one's \
         size is the diameter of a cylinder through the box that holds it, over L, and one a fifth \
         of the system across makes the run growing_particles.</p>\n",
    );
    if profile == Profile::Quick {
        h += "<p class=\"note\">Quick profile: L = 20 d0, 5 L of sliding, 100 bins, one seed; d* = 0.2 L \
              does not enter at this d0 (d*/8 below every pair), so only the p_N and sigma_m trends \
              are tested. The 20 d0 box also overstates tau_m (its strength test peaks 13 % above \
              that of a box three times as large), and its coarse layer carries less than the \
              paper-size one: section 3's p_T at the shear strength is reproduced at the paper's \
              size by <code>cgdem --threads 2 sliding configs/sliding-paper-shear-band.toml</code> \
              (Fig. 3b's material, about 45 minutes; docs/sliding.md). The same shear band is also \
              run on a 40 d0 box (d0 = 0.025 L, d* = 0.1 L = 4 d0 as on the 20 d0 box, so the same \
              discrete material; 160 bins; its own tau_m): p_T / tau_m rises with the resolution, \
              about linearly in d0 / L, and the line through the two boxes is read at the paper's \
              d0 = 0.01 L (the last figure panel and its claim).</p>\n";
    }
    h += "<p>tau_m is measured, not taken from the paper: the shear patch test (paper 000 Fig. 4c) \
          on each material's own relaxed box (the sliding run's recipe, law and seed, before the cut), \
          top wall moved along x at constant separation, strain rate 1e-5 per step; tau_m is the \
          peak of sigma_xy, sigma_t the peak of the tensile test. After its peak the box flows in \
          stick-slip; tau_flow is the mean sigma_xy from 0.15 strain past the peak to the end of the \
          test (0.6 past the peak), with the saw-tooth's range beside it.</p>\n";
    h += "<table><tr><th>sigma_m (E)</th><th>L (d0)</th><th>tau_m / sigma_m</th><th>at shear strain</th>\
          <th>tau_flow / sigma_m (range)</th><th>sigma_t / sigma_m</th><th>particles</th>\
          <th>tests (s)</th></tr>\n";
    for (s, job) in strengths.iter().zip(jobs) {
        let m = &s.strength;
        let flow = m.tau_flow.map_or("(test too short)".to_string(), |f| {
            format!(
                "{:.3} ({:.3}-{:.3})",
                f.mean / m.sigma_m,
                f.min / m.sigma_m,
                f.max / m.sigma_m
            )
        });
        h += &format!(
            "<tr><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{}</td><td>{:.3}</td><td>{}</td><td>{:.0}</td></tr>\n",
            m.sigma_m,
            (1.0 / job.sliding.d0_over_l).round(),
            m.tau_over_sigma_m(),
            m.shear.strain_at_peak,
            esc(&flow),
            m.sigma_t / m.sigma_m,
            m.particles,
            m.shear.wall_seconds + m.tensile.wall_seconds
        );
    }
    h += "</table>\n";
    h += "<table><tr><th>p_N (E)</th><th>sigma_m (E)</th><th>L (d0)</th><th>regime</th><th>rho_TBL / rho_0</th>\
          <th>h_TBL / H</th><th>agitation (v0)</th><th>p_T (E)</th><th>p_T / tau_m</th>\
          <th>p_T / (tau_m rho_TBL / rho_0)</th><th>p_T / tau_flow</th><th>TBL at a body from (L)</th>\
          <th>interior windows</th><th>interior p_T / tau_m</th>\
          <th>wear particles (steady mean)</th><th>largest wear particle (L)</th>\
          <th>particles</th><th>run (s)</th></tr>\n";
    for o in outs {
        let r = &o.summary;
        h += &format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{}</td><td>{:.2e}</td><td>{:.2}</td><td>{:.2}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.0}</td></tr>\n",
            r.p_n,
            r.strength,
            l_over_d0(r.d0_over_l),
            esc(r.regime.label()),
            r.rho_tbl,
            r.h_tbl,
            r.agitation.map_or("-".to_string(), |v| format!("{v:.3}")),
            r.p_t,
            r.p_t_over_tau_m,
            r.p_t_over_tau_rho,
            r.p_t_over_tau_flow
                .map_or("-".to_string(), |v| format!("{v:.2}")),
            r.body_reached_at_l
                .map_or("never".to_string(), |v| format!("{v:.2}")),
            r.interior.as_ref().map_or(0, |i| i.windows),
            r.interior
                .as_ref()
                .map_or("-".to_string(), |i| format!("{:.2}", i.p_t_over_tau_m)),
            r.wear_particles
                .map_or("-".to_string(), |w| format!("{:.1}", w.steady_count)),
            r.wear_particles.map_or("-".to_string(), |w| {
                if w.max_largest_over_l > 0.0 {
                    format!("{:.3} at {:.1} L", w.max_largest_over_l, w.max_at_l)
                } else {
                    "none".to_string()
                }
            }),
            r.particles,
            r.run_seconds
        );
    }
    h += "</table>\n";
    if let Some(s) = strengths.iter().find(|s| s.strength.sigma_m == 0.1) {
        h += &format!(
            "<figure>{}<figcaption>strength tests of the sigma_m = 0.1 E material: shear (left) and \
             tension (right), stresses over sigma_m</figcaption></figure>\n",
            s.figure
        );
    }
    if let Some(o) = outs.iter().find(|o| o.summary.p_n == 0.02) {
        h += &format!(
            "<figure>{}<figcaption>p_N = 0.02 E, sigma_m = {} E: velocity and density profiles \
             (TBL boundaries dashed)</figcaption></figure>\n<figure>{}<figcaption>the same run, \
             coloured by initial height</figcaption></figure>\n",
            o.profiles, o.summary.strength, o.snapshot
        );
    }
    h
}
