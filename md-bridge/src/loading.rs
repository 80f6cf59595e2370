//! Constant-rate loading to failure, shared by the silica and model-material workflows: the
//! deformation runs in short chunks and a chunk-averaged stress is recorded after each, so the
//! curve and its peak come back to Rust while LAMMPS keeps one continuous `fix deform` ramp.

use crate::error::{MdError, Result};
use crate::lammps::Lammps;
use serde::{Deserialize, Serialize};

/// A strain-stress history: (engineering strain, stress in output units).
pub type Curve = Vec<[f64; 2]>;

/// Peak of a loading curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Strength {
    /// Peak stress (Pa for silica, reduced units for the model material).
    pub peak_stress: f64,
    pub peak_strain: f64,
    /// False when the peak is the last point (the sample had not failed/yielded yet).
    pub peak_reached: bool,
    pub curve: Curve,
}

/// Chunking of a ramp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// MD steps per recorded point (the stress is averaged over them).
    pub steps_per_point: u64,
    /// Upper bound on recorded points (the whole ramp).
    pub points: u64,
    /// Factor from LAMMPS stress units to output units.
    pub stress_scale: f64,
}

/// Runs the already-defined deformation fixes, recording (strain, averaged stress) until
/// `max_strain`, or until failure: strain 0.05 past the peak with stress below `drop` x peak.
/// `stress_var` and `strain_var` are equal-style variable names.
pub fn load_curve(
    lmp: &Lammps,
    ramp: &Ramp,
    stress_var: &str,
    strain_var: &str,
    max_strain: f64,
    drop: f64,
) -> Result<Curve> {
    let chunk = ramp.steps_per_point;
    // `start`/`stop` make fix deform see one continuous ramp across the chunked runs; without
    // them every `run ... pre no` restarts the ramp from the box of the first run's init.
    let total = ramp.points * chunk;
    lmp.commands(&format!(
        "fix sav all ave/time 1 {chunk} {chunk} v_{stress_var}\nvariable sava equal f_sav"
    ))?;
    let mut curve: Curve = Vec::new();
    let (mut peak, mut peak_strain) = (f64::MIN, 0.0);
    for k in 0..ramp.points {
        let pre = if k == 0 { "yes" } else { "no" };
        lmp.command(&format!(
            "run {chunk} start 0 stop {total} pre {pre} post no"
        ))?;
        let strain = lmp.variable(strain_var)?;
        let s = lmp.variable("sava")? * ramp.stress_scale;
        curve.push([strain, s]);
        if s > peak {
            (peak, peak_strain) = (s, strain);
        }
        // A thermal blip is not a failure: require distance past the peak as well as a drop.
        if strain >= max_strain || (strain > peak_strain + 0.05 && s < drop * peak && peak > 0.0) {
            break;
        }
    }
    lmp.command("unfix sav")?;
    Ok(curve)
}

/// Simple shear in xy at constant volume and temperature `t` (thermostat damping `t_damp`, SLLOD
/// with the streaming velocity removed from the temperature) from the box tilt `xy0`, recorded by
/// [`load_curve`] as engineering shear strain (xy - xy0) / ly against -pxy. Leaves no fix behind.
#[allow(clippy::too_many_arguments)]
pub fn simple_shear(
    lmp: &Lammps,
    xy0: f64,
    rate: f64,
    t: f64,
    t_damp: f64,
    ramp: &Ramp,
    max_strain: f64,
    drop: f64,
) -> Result<Curve> {
    lmp.commands(&format!(
        "variable xy0 equal {xy0}
variable gxy equal (xy-v_xy0)/ly
variable sxy equal -pxy
compute tdef all temp/deform
fix def all deform 1 xy erate {rate} remap v flip no
fix md all nvt/sllod temp {t} {t} {t_damp}
fix_modify md temp tdef"
    ))?;
    let curve = load_curve(lmp, ramp, "sxy", "gxy", max_strain, drop)?;
    lmp.commands("unfix md\nunfix def\nuncompute tdef")?;
    Ok(curve)
}

/// The maximum of a curve; an error if there is no positive stress at all.
pub fn peak_of(curve: Curve, what: &str) -> Result<Strength> {
    let (i, p) = curve
        .iter()
        .enumerate()
        .max_by(|a, b| a.1[1].total_cmp(&b.1[1]))
        .ok_or_else(|| MdError::measurement(what, "empty stress-strain curve"))?;
    if p[1].is_nan() || p[1] <= 0.0 {
        return Err(MdError::measurement(
            what,
            format!("no positive stress (peak {})", p[1]),
        ));
    }
    Ok(Strength {
        peak_stress: p[1],
        peak_strain: p[0],
        peak_reached: i + 1 < curve.len(),
        curve,
    })
}
