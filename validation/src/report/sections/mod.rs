//! The report's sections, in page order. A section is a module with `pub const SECTION: Section`;
//! adding one is writing that module and one line in [`all`].

pub mod calibration;
pub mod compare;
pub mod force_laws;
pub mod junction;
pub mod md;
pub mod md_chain;
pub mod patch;
pub mod performance;
pub mod plastic;
pub mod sliding;
pub mod two_particle;

use super::Section;

/// Every section, in the order of the page.
pub fn all() -> Vec<Section> {
    vec![
        force_laws::SECTION,
        two_particle::SECTION,
        patch::HCP,
        patch::AMORPHOUS,
        calibration::SECTION,
        md::SILICA,
        md_chain::SECTION,
        md::MODEL,
        performance::SECTION,
        junction::SECTION,
        compare::SECTION,
        sliding::SECTION,
        plastic::SECTION,
    ]
}
