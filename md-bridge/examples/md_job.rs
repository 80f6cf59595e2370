//! Runs one MD job JSON (silica, model or junction) in this process and prints the output as JSON: a way to exercise the
//! workflows without the `cgdem` binary (e.g. while experimenting with protocols).
//! Usage: `cargo run --release -p md-bridge --example md_job -- JOB.json`

use md_bridge::job::{Job, JobOutput};
use md_bridge::{Lammps, Venv};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("usage: md_job JOB.json")?;
    let job: Job = serde_json::from_str(&std::fs::read_to_string(&path)?)?;
    let venv = Venv::locate();
    let lmp = Lammps::new(&venv, &["-log", "none", "-screen", "none", "-nocite"])?;
    let out = match &job {
        Job::Junction(c) => JobOutput::Junction(Box::new(md_bridge::junction::run(&lmp, c)?)),
        Job::Model(c) => JobOutput::Model(Box::new(md_bridge::model::run(&lmp, c)?)),
        Job::Silica(c) => {
            let pot = venv.potential(md_bridge::silica::POTENTIAL)?;
            JobOutput::Silica(Box::new(md_bridge::silica::run(
                &lmp,
                &pot,
                c,
                &md_bridge::stages::Stages::none(),
            )?))
        }
        other => {
            return Err(
                format!("md_job runs silica, junction and model jobs, not {other:?}").into(),
            )
        }
    };
    println!("{}", serde_json::to_string_pretty(&out)?);
    Ok(())
}
