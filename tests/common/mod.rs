//! Helpers shared by the integration tests: the exact topology oracle, test
//! fields, and the comparison of a checked mesh with the oracle.
#![allow(dead_code)]

pub mod fields;
pub mod oracle;

use oracle::Topology;
use tmc::check::MeshReport;

/// Compares the report of an extracted mesh with the oracle's topology of
/// the same grid and isovalue (closed case: nothing positive on the grid
/// boundary). Returns a description of every disagreement.
pub fn compare_with_oracle(report: &MeshReport, topo: &Topology) -> Result<(), String> {
    let mut problems = Vec::new();
    if !report.is_closed_manifold() {
        problems.push(format!("mesh is not a closed manifold: {report:?}"));
    }
    match (topo.surface_components, topo.surface_euler) {
        (Some(components), Some(euler)) => {
            if report.components != components {
                problems.push(format!(
                    "components: mesh {} vs oracle {components}",
                    report.components
                ));
            }
            if report.euler != euler {
                problems.push(format!("euler: mesh {} vs oracle {euler}", report.euler));
            }
        }
        _ => problems.push("oracle: surface is not closed (positive sample on the border)".into()),
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("; "))
    }
}
