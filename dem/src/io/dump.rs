//! LAMMPS-style text dumps (`ITEM: TIMESTEP ...`), which OVITO opens directly: one frame per call,
//! columns id, type (group + 1), x, y, z, radius, vx, vy, vz, wx, wy, wz, the image flags ix, iy, iz
//! (box lengths each particle has been wrapped by: x + ix L_x is its continuous trajectory), then any
//! integer labels the caller adds (a scenario's `body`: which body each particle initially belonged
//! to, for colouring).

use std::io::Write;
use std::path::Path;

use crate::error::{DemError, Result};
use crate::sim::Simulation;

/// A per-particle integer column of a dump.
pub type Label<'a> = (&'a str, &'a [u32]);

/// Appends one frame of `sim` to the dump file at `path` (created if missing).
pub fn append_frame(sim: &Simulation, path: &Path) -> Result<()> {
    append_labeled_frame(sim, path, &[])
}

/// [`append_frame`] with extra integer columns, one value per particle.
pub fn append_labeled_frame(sim: &Simulation, path: &Path, labels: &[Label]) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| DemError::io(dir, e))?;
    }
    let file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| DemError::io(path, e))?;
    let mut w = std::io::BufWriter::new(file);
    write_labeled_frame(sim, &mut w, labels).map_err(|e| DemError::io(path, e))?;
    w.flush().map_err(|e| DemError::io(path, e))
}

/// Writes one frame to any writer.
pub fn write_frame(sim: &Simulation, w: &mut impl Write) -> std::io::Result<()> {
    write_labeled_frame(sim, w, &[])
}

/// Writes one frame with extra integer columns (each must hold one value per particle).
pub fn write_labeled_frame(
    sim: &Simulation,
    w: &mut impl Write,
    labels: &[Label],
) -> std::io::Result<()> {
    let p = &sim.particles;
    if let Some((name, v)) = labels.iter().find(|(_, v)| v.len() != p.len()) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "label '{name}' has {} values for {} particles",
                v.len(),
                p.len()
            ),
        ));
    }
    let b = &sim.sim_box;
    writeln!(w, "ITEM: TIMESTEP\n{}", sim.step_count())?;
    writeln!(w, "ITEM: NUMBER OF ATOMS\n{}", p.len())?;
    let flags: Vec<&str> = b
        .periodic
        .iter()
        .map(|&q| if q { "pp" } else { "ff" })
        .collect();
    writeln!(w, "ITEM: BOX BOUNDS {} {} {}", flags[0], flags[1], flags[2])?;
    for a in 0..3 {
        writeln!(w, "{:.17e} {:.17e}", b.lo[a], b.hi[a])?;
    }
    write!(
        w,
        "ITEM: ATOMS id type x y z radius vx vy vz omegax omegay omegaz ix iy iz"
    )?;
    for (name, _) in labels {
        write!(w, " {name}")?;
    }
    writeln!(w)?;
    for i in 0..p.len() {
        let (x, v, o) = (p.pos[i], p.vel[i], p.omega[i]);
        write!(
            w,
            "{} {} {:.10e} {:.10e} {:.10e} {:.10e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e}",
            i + 1,
            p.group[i] + 1,
            x.x,
            x.y,
            x.z,
            p.radius[i],
            v.x,
            v.y,
            v.z,
            o.x,
            o.y,
            o.z
        )?;
        // Image flags (box lengths the particle has been wrapped by), so that OVITO's "unwrap
        // trajectories" and LAMMPS tools follow a particle across the periodic boundaries.
        let n = sim.neighbors().wraps.get(i).copied().unwrap_or([0; 3]);
        write!(w, " {} {} {}", n[0], n[1], n[2])?;
        for (_, v) in labels {
            write!(w, " {}", v[i])?;
        }
        writeln!(w)?;
    }
    Ok(())
}
