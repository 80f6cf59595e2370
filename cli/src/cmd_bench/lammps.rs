//! The LAMMPS side of the bench: a data file of the workload's particles and an input running
//! `pair_style gran/hooke/history` with `fix nve/sphere`, timed on 1 process or under the venv's
//! `mpirun`. LAMMPS's granular styles compute overlapping pairs only, so each workload gives LAMMPS
//! radii whose overlaps are the pairs cgdem computes ([`System::radius`]).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, Context, Result};
use md_bridge::venv::Venv;

use super::Prepared;

/// What LAMMPS is given besides the positions and velocities.
pub(crate) struct System {
    /// Radii as LAMMPS sees them.
    pub radius: Vec<f64>,
    /// Mass density written to the data file.
    pub density: f64,
    /// Hookean normal and tangential stiffness of `gran/hooke/history`.
    pub k_n: f64,
    pub k_t: f64,
    /// Neighbour skin (cgdem's).
    pub skin: f64,
}

/// Writes `bench.data` and `in.bench` into `dir`; returns the input's path.
pub(crate) fn write_inputs(dir: &Path, prep: &Prepared, steps: u64, dt: f64) -> Result<PathBuf> {
    let (p, bx, sys) = (&prep.particles, &prep.sim_box, &prep.lammps);
    std::fs::create_dir_all(dir)?;
    let data = dir.join("bench.data");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&data)?);
    writeln!(f, "cgdem bench system\n\n{} atoms\n1 atom types\n", p.len())?;
    for (a, name) in ["x", "y", "z"].iter().enumerate() {
        writeln!(f, "{:.17e} {:.17e} {name}lo {name}hi", bx.lo[a], bx.hi[a])?;
    }
    writeln!(f, "\nAtoms # sphere\n")?;
    for i in 0..p.len() {
        let x = p.pos[i];
        writeln!(
            f,
            "{} 1 {:.17e} {:.17e} {:.17e} {:.17e} {:.17e}",
            i + 1,
            2.0 * sys.radius[i],
            sys.density,
            x.x,
            x.y,
            x.z
        )?;
    }
    writeln!(f, "\nVelocities\n")?;
    for i in 0..p.len() {
        let v = p.vel[i];
        writeln!(f, "{} {:.17e} {:.17e} {:.17e} 0 0 0", i + 1, v.x, v.y, v.z)?;
    }
    f.flush()?;
    let input = dir.join("in.bench");
    std::fs::write(
        &input,
        format!(
            "units lj\natom_style sphere\nboundary p p p\ncomm_modify vel yes\nnewton off\n\
             read_data {data}\n\
             pair_style gran/hooke/history {kn:.17e} {kt:.17e} 0.0 0.0 0.5 1\npair_coeff * *\n\
             neighbor {skin:.17e} bin\nneigh_modify delay 0 every 1 check yes\n\
             fix 1 all nve/sphere\ntimestep {dt:.17e}\nthermo 0\nrun 1\nrun {steps}\n",
            data = data.display(),
            kn = sys.k_n,
            kt = sys.k_t,
            skin = sys.skin,
        ),
    )?;
    Ok(input)
}

/// A timed LAMMPS run.
pub(crate) struct Run {
    /// Loop seconds of the timed run.
    pub secs: f64,
    pub atoms: usize,
    /// "Total # of neighbors" at the end (pairs of the list; with `newton off` on several processes,
    /// pairs across a boundary count twice).
    pub neighbors: Option<u64>,
    /// "Neighbor list builds" of the timed run.
    pub builds: Option<u64>,
}

/// Runs LAMMPS from `venv` on `procs` processes.
pub(crate) fn time(venv: &Venv, input: &Path, steps: u64, procs: usize) -> Result<Run> {
    let exe = venv.lmp_exe()?;
    let log = input.with_file_name(format!("log.{procs}p.lammps"));
    let mut cmd = if procs > 1 {
        let mut c = Command::new(venv.mpirun());
        c.arg("-np").arg(procs.to_string()).arg(&exe);
        c
    } else {
        Command::new(&exe)
    };
    let out = cmd
        .args(["-screen", "none", "-nocite", "-log"])
        .arg(&log)
        .arg("-in")
        .arg(input)
        .env("LD_LIBRARY_PATH", venv.root.join("lib"))
        .env("OMP_NUM_THREADS", "1")
        .output()
        .with_context(|| format!("starting {}", exe.display()))?;
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    if !out.status.success() {
        bail!(
            "lmp on {procs} process(es) failed ({}): {} {}",
            out.status,
            text.lines().rev().take(5).collect::<Vec<_>>().join(" | "),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    parse_log(&text, steps)
}

/// Reads the timed (last) run's loop time, atoms, neighbour count and list builds from a log.
fn parse_log(text: &str, steps: u64) -> Result<Run> {
    // "Loop time of 12.3 on 1 procs for 300 steps with 51200 atoms": the last one is the timed run.
    let (at, line) = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("Loop time of") && l.contains(&format!("for {steps} steps")))
        .last()
        .context("no loop time in the LAMMPS log")?;
    let w: Vec<&str> = line.split_whitespace().collect();
    let after = |key: &str| -> Option<u64> {
        text.lines()
            .skip(at)
            .find(|l| l.starts_with(key))
            .and_then(|l| l.rsplit('=').next())
            .and_then(|v| v.trim().parse().ok())
    };
    Ok(Run {
        secs: w[3].parse()?,
        atoms: w[w.len() - 2].parse()?,
        neighbors: after("Total # of neighbors"),
        builds: after("Neighbor list builds"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_timed_runs_figures_are_read_from_the_log() {
        let log = "Loop time of 0.5 on 1 procs for 1 steps with 10 atoms\n\
                   Total # of neighbors = 7\nNeighbor list builds = 0\n\
                   Loop time of 2.25 on 2 procs for 300 steps with 384 atoms\n\
                   Total # of neighbors = 1152\nAve neighs/atom = 3\nNeighbor list builds = 4\n";
        let r = parse_log(log, 300).unwrap();
        assert_eq!((r.secs, r.atoms), (2.25, 384));
        assert_eq!((r.neighbors, r.builds), (Some(1152), Some(4)));
        assert!(parse_log(log, 500).is_err());
    }
}
