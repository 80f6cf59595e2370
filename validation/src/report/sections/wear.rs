//! Wear sections whose scenarios are not on main yet: each says so in one line. When a scenario
//! lands, its section replaces the placeholder here with a module of its own (see `sections::all`).

use crate::report::{Context, Section, SectionOutput};
use crate::Result;

fn pending(what: &str) -> Result<SectionOutput> {
    Ok(SectionOutput {
        html: format!("<p><b>Not on main yet:</b> {what}</p>\n"),
        ..SectionOutput::default()
    })
}

pub const JUNCTION: Section = Section {
    id: "wear-junction",
    title: "Wear: junction shear and d* (paper 000 section 4, eq 22, Table 6)",
    run: |_: &Context| {
        pending("the junction scenario (snapshots, verdicts, outcome maps, d* brackets from DEM, MD and eq 22, runs against Table 6) is being built and will add its claims here.")
    },
};

pub const SLIDING: Section = Section {
    id: "wear-sliding",
    title: "Wear: third-body sliding (paper 004)",
    run: |_: &Context| {
        pending("the third-body sliding scenario (velocity and density profiles, p_T) is being built and will add its claims here.")
    },
};

pub const IMPACT: Section = Section {
    id: "wear-impact",
    title: "Wear: plastic impact and scratch (paper 001)",
    run: |_: &Context| {
        pending("the impact and scratch scenarios (wear volume against eq 16, energy balance eqs 21-23) are being built and will add their claims here.")
    },
};
