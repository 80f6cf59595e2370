//! The LAMMPS side of every bench (`cgdem bench`, both workloads, and the report's performance
//! section): a data file of the particles and an input running `pair_style gran/hooke/history` with
//! `fix nve/sphere`, timed on 1 process or under the venv's `mpirun`. LAMMPS's granular styles compute
//! overlapping pairs only, so each workload gives LAMMPS radii whose overlaps are the pairs cgdem
//! computes ([`System::radius`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use dem::{Particles, SimBox};
use md_bridge::venv::Venv;

use crate::{Result, ValidationError};

/// What LAMMPS is given besides the positions and velocities.
#[derive(Debug, Clone, PartialEq)]
pub struct System {
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

/// Writes `bench.data` and `in.bench` (one untimed step, then `steps` timed ones) into `dir`;
/// returns the input's path. The input reads its data relative to `dir`, where [`time`] runs it.
pub fn write_inputs(
    dir: &Path,
    p: &Particles,
    bx: &SimBox,
    sys: &System,
    steps: u64,
    dt: f64,
) -> Result<PathBuf> {
    if sys.radius.len() != p.len() {
        return Err(ValidationError::Report(format!(
            "LAMMPS bench: {} radii for {} particles",
            sys.radius.len(),
            p.len()
        )));
    }
    std::fs::create_dir_all(dir).map_err(|e| ValidationError::io(dir, e))?;
    let data = dir.join("bench.data");
    // Writing into a String cannot fail.
    let mut f = String::new();
    let _ = writeln!(f, "cgdem bench system\n\n{} atoms\n1 atom types\n", p.len());
    for (a, name) in ["x", "y", "z"].iter().enumerate() {
        let _ = writeln!(f, "{:.17e} {:.17e} {name}lo {name}hi", bx.lo[a], bx.hi[a]);
    }
    let _ = writeln!(f, "\nAtoms # sphere\n");
    for i in 0..p.len() {
        let x = p.pos[i];
        let _ = writeln!(
            f,
            "{} 1 {:.17e} {:.17e} {:.17e} {:.17e} {:.17e}",
            i + 1,
            2.0 * sys.radius[i],
            sys.density,
            x.x,
            x.y,
            x.z
        );
    }
    let _ = writeln!(f, "\nVelocities\n");
    for i in 0..p.len() {
        let v = p.vel[i];
        let _ = writeln!(f, "{} {:.17e} {:.17e} {:.17e} 0 0 0", i + 1, v.x, v.y, v.z);
    }
    std::fs::write(&data, f).map_err(|e| ValidationError::io(&data, e))?;
    let input = dir.join("in.bench");
    std::fs::write(
        &input,
        format!(
            "units lj\natom_style sphere\nboundary p p p\ncomm_modify vel yes\nnewton off\n\
             read_data bench.data\n\
             pair_style gran/hooke/history {kn:.17e} {kt:.17e} 0.0 0.0 0.5 1\npair_coeff * *\n\
             neighbor {skin:.17e} bin\nneigh_modify delay 0 every 1 check yes\n\
             fix 1 all nve/sphere\ntimestep {dt:.17e}\nthermo 0\nrun 1\nrun {steps}\n",
            kn = sys.k_n,
            kt = sys.k_t,
            skin = sys.skin,
        ),
    )
    .map_err(|e| ValidationError::io(&input, e))?;
    Ok(input)
}

/// A timed LAMMPS run.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Loop seconds of the timed run.
    pub secs: f64,
    pub atoms: usize,
    /// "Total # of neighbors" at the end (pairs of the list; with `newton off` on several processes,
    /// pairs across a boundary count twice).
    pub neighbors: Option<u64>,
    /// "Neighbor list builds" of the timed run.
    pub builds: Option<u64>,
}

/// Runs LAMMPS from `venv` on `procs` processes (under the venv's `mpirun` when more than one).
pub fn time(venv: &Venv, input: &Path, steps: u64, procs: usize) -> Result<Run> {
    let (dir, name) = match (input.parent(), input.file_name()) {
        (Some(d), Some(n)) => (d, n.to_string_lossy()),
        _ => {
            return Err(ValidationError::Report(format!(
                "LAMMPS bench: {} is not a file path",
                input.display()
            )))
        }
    };
    let log = format!("log.{procs}p.lammps");
    let text = venv
        .run_lmp(dir, &name, &log, procs)
        .map_err(|e| ValidationError::Report(format!("LAMMPS bench: {e}")))?;
    parse_log(&text, steps).map_err(|e| ValidationError::Report(format!("{log}: {e}")))
}

/// Reads the timed (last) run's loop time, atoms, neighbour count and list builds from a log.
fn parse_log(text: &str, steps: u64) -> std::result::Result<Run, String> {
    // "Loop time of 12.3 on 1 procs for 300 steps with 51200 atoms": the last one is the timed run.
    let (at, line) = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("Loop time of") && l.contains(&format!("for {steps} steps")))
        .last()
        .ok_or("no loop time in the LAMMPS log")?;
    let w: Vec<&str> = line.split_whitespace().collect();
    let bad = || format!("unreadable loop time line: {line}");
    let after = |key: &str| -> Option<u64> {
        text.lines()
            .skip(at)
            .find(|l| l.starts_with(key))
            .and_then(|l| l.rsplit('=').next())
            .and_then(|v| v.trim().parse().ok())
    };
    Ok(Run {
        secs: w.get(3).and_then(|v| v.parse().ok()).ok_or_else(bad)?,
        atoms: w
            .iter()
            .rev()
            .nth(1)
            .and_then(|v| v.parse().ok())
            .ok_or_else(bad)?,
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
        assert!(parse_log("Loop time of x on 1 procs for 300 steps with 9 atoms", 300).is_err());
    }
}
