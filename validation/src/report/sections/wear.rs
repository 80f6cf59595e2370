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

pub const SLIDING: Section = Section {
    id: "wear-sliding",
    title: "Wear: third-body sliding (paper 004)",
    run: |_: &Context| {
        pending("the third-body sliding scenario (velocity and density profiles, p_T) is being built and will add its claims here.")
    },
};
