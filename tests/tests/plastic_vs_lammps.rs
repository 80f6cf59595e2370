//! The plastic-wear model's contact loop against LAMMPS, which paper 001 ran: with the surface too hard
//! to flow, an oblique impact of the 3 mm sphere is a multi-contact Hertz collision with Coulomb
//! friction, tangential history and spin. LAMMPS (`pair_style granular`, `hertz/material` +
//! `tangential linear_history`, `fix nve/sphere`, velocity Verlet) runs the deck that
//! `dem::scenario::plastic::lammps` writes, from the same atoms, time step and number of steps; the
//! rebound speed, angle and spin agree to the integrators' O(dt) difference. Needs the project venv
//! (fails, never skips, without it).

use std::path::PathBuf;

use dem::scenario::plastic::lammps::{impact_deck, read_result, DATA_FILE};
use dem::scenario::plastic::{run_impact, ImpactConfig};
use md_bridge::venv::Venv;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "cgdem-plastic-lammps-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn lammps(cfg: &ImpactConfig, steps: u64, name: &str) -> [f64; 6] {
    let venv = Venv::locate();
    if let Err(e) = venv.check() {
        panic!(
            "LAMMPS venv missing or broken ({e}); run `{}`",
            md_bridge::SETUP_COMMAND
        );
    }
    let d = dir(name);
    let deck = impact_deck(cfg, steps).unwrap();
    std::fs::write(d.join("in.plastic"), &deck.input).unwrap();
    std::fs::write(d.join(DATA_FILE), &deck.data).unwrap();
    let log = venv.run_lmp(&d, "in.plastic", "log.lammps", 1).unwrap();
    let r = read_result(&log).expect("RESULT line");
    std::fs::remove_dir_all(&d).ok();
    r
}

#[test]
fn an_unworn_oblique_impact_rebounds_as_in_lammps() {
    for (angle, modulus) in [(45.0, "lammps"), (25.0, "lammps"), (60.0, "rigid")] {
        let cfg: ImpactConfig = toml::from_str(&format!(
            "[model]\nhardness = 1e15\ncontact_modulus = \"{modulus}\"\n\
             [projectile]\nradius = 0.003\ndensity = 2500.0\n\
             [impact]\nspeed = 35.0\nangle_deg = {angle}\naim_offset = [1e-4, 5e-5]\n"
        ))
        .unwrap();
        let ours = run_impact(&cfg).unwrap();
        let r = lammps(&cfg, ours.steps, &format!("{angle}"));
        let speed = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let (cor, theta_r, spin) = (
            speed / 35.0,
            r[2].atan2(r[0]).to_degrees(),
            (r[3] * r[3] + r[4] * r[4] + r[5] * r[5]).sqrt(),
        );
        println!(
            "{angle} deg ({modulus}): cgdem COR {:.6} angle {:.4} spin {:.2}; LAMMPS COR {cor:.6} angle {theta_r:.4} spin {spin:.2} ({} steps of {:.3e} s)",
            ours.cor, ours.rebound_angle_deg, ours.rebound_spin, ours.steps, ours.time_step
        );
        // Friction took energy (the rebound is not elastic) and both agree on how much.
        assert!(ours.cor < 0.999);
        assert!((ours.cor - cor).abs() < 2e-3, "COR");
        assert!(
            (ours.rebound_angle_deg - theta_r).abs() < 0.2,
            "rebound angle"
        );
        assert!((ours.rebound_spin - spin).abs() / spin < 0.01, "spin");
    }
}
